// libFuzzer target: the .klg log reader (ElasticFusion's format) on arbitrary files: the frame index when
// opened, then every frame decoded (zlib depth, JPEG or raw colour). Errors must name the file; a frame that
// cannot be read is passed (as `vifusion run` skips it) and the next one is still read.

#include <cstddef>
#include <cstdint>
#include <memory>
#include <span>

#include "fuzz_support.hpp"
#include "vifusion/datasets/klg_reader.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace vifusion;
  static const fuzz::ScratchFolder folder;
  static RgbdFrame frame;
  const auto path = folder.write("log.klg", std::span<const std::uint8_t>(data, size));
  std::unique_ptr<datasets::KlgReader> reader;
  if (!fuzz::parsedOrNamedError({"log.klg"}, [&] { reader = std::make_unique<datasets::KlgReader>(path); })) return 0;
  // Every call moves past one frame, read or not, so the frame count bounds the calls.
  std::size_t calls = 0;
  bool more = true;
  while (more) {
    fuzz::require(++calls <= reader->frameCount() + 1);
    fuzz::parsedOrNamedError({"log.klg"}, [&] { more = reader->nextFrame(frame); });
  }
  return 0;
}
