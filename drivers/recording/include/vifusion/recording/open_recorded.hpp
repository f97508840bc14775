#pragma once
// Every recorded source behind one call: `rec:FILE.mcap` (a vifusion recording) and the dataset specs
// of datasets::openDataset (tum:, icl:, 7scenes:, klg:, dataset:).

#include <memory>
#include <string>

#include "vifusion/datasets/dataset_reader.hpp"

namespace vifusion::recording {

/// @throws vifusion::Error for an unknown spec or an unreadable recording or dataset (naming it).
std::unique_ptr<datasets::DatasetReader> openRecorded(const std::string& spec);

}  // namespace vifusion::recording
