#pragma once
// Opens vifusiond's source. Dataset specs go to datasets::openDataset; `sim:NAME` is generated
// once into <out>/sim_NAME by the `vifusion sim` program installed beside vifusiond (the simulator
// lives in the CLI), then replayed like any dataset directory.

#include <memory>
#include <string>

#include "vifusion/datasets/dataset_reader.hpp"

namespace vifusion::daemon {

/// Throws vifusion::Error saying what failed (generation, or the dataset's own error).
std::unique_ptr<datasets::DatasetReader> openSource(const std::string& source, const std::string& out_dir);

}  // namespace vifusion::daemon
