// fuzz_seeds OUT_DIR DATA_DIR SOURCE_DIR: writes every fuzz target's seed corpus into OUT_DIR/<target>, cut
// from the test data in DATA_DIR (../shared/data) and written by our own writers; SOURCE_DIR is the checkout
// (the shipped vifusiond.yaml).

#include <cstdio>
#include <exception>
#include <filesystem>

#include "seed_writer.hpp"

int main(int argc, char** argv) {
  if (argc != 4) {
    std::fprintf(stderr, "usage: fuzz_seeds OUT_DIR DATA_DIR SOURCE_DIR\n");
    return 2;
  }
  using namespace vifusion::fuzz::seeds;
  const std::filesystem::path out = argv[1], data = argv[2], source = argv[3];
  try {
    writeCalibrationSeeds(out);
    writeDatasetListSeeds(out, data);
    writeDaemonConfigSeeds(out, source);
    writeImageSeeds(out, data);
    writeKlgSeeds(out, data);
    writeMapFileSeeds(out);
    writePlySeeds(out, data);
    writeCdrSeeds(out);
  } catch (const std::exception& error) {
    std::fprintf(stderr, "fuzz_seeds: %s\n", error.what());
    return 1;
  }
  return 0;
}
