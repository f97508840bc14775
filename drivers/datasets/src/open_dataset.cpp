#include <string_view>

#include "vifusion/core/error.hpp"
#include "vifusion/datasets/dataset_reader.hpp"
#include "vifusion/datasets/icl_nuim_reader.hpp"
#include "vifusion/datasets/klg_reader.hpp"
#include "vifusion/datasets/seven_scenes_reader.hpp"
#include "vifusion/datasets/tum_reader.hpp"
#include "vifusion/datasets/vifusion_dataset_reader.hpp"

namespace vifusion::datasets {
namespace {

constexpr std::string_view kValidSpecs = "tum:DIR, icl:DIR, 7scenes:DIR, klg:FILE, dataset:DIR";

}  // namespace

std::unique_ptr<DatasetReader> openDataset(const std::string& spec) {
  const std::size_t colon = spec.find(':');
  const std::string prefix = colon == std::string::npos ? spec : spec.substr(0, colon);
  const std::string path = colon == std::string::npos ? std::string() : spec.substr(colon + 1);
  const bool known =
      prefix == "tum" || prefix == "icl" || prefix == "7scenes" || prefix == "klg" || prefix == "dataset";
  if (known && path.empty()) throw Error("dataset source '" + spec + "': no path after '" + prefix + ":'");
  if (prefix == "tum") return std::make_unique<TumReader>(path);
  if (prefix == "icl") return std::make_unique<IclNuimReader>(path);
  if (prefix == "7scenes") return std::make_unique<SevenScenesReader>(path);
  if (prefix == "klg") return std::make_unique<KlgReader>(path);
  if (prefix == "dataset") return std::make_unique<VifusionDatasetReader>(path);
  if (prefix == "sim" || prefix == "rec" || prefix == "zr300") {
    throw Error("dataset source '" + spec + "': '" + prefix +
                "' is opened by the vifusion CLI, not by a dataset reader (a sim:NAME preset is generated into a "
                "directory, which then opens as dataset:DIR); dataset readers take " +
                std::string(kValidSpecs));
  }
  throw Error("unknown dataset source '" + spec + "'; valid: " + std::string(kValidSpecs));
}

}  // namespace vifusion::datasets
