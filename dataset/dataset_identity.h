#pragma once
// What makes a batch's directory one dataset: the inputs and settings that
// decide its frames (dataset.json), so that a batch refuses to write into a
// directory another batch made, where the two would mix frames and labels
// under one manifest. The same batch made again is let through: it writes
// the same files.
#include <nlohmann/json.hpp>
#include <string>

#include "dataset/batch_options.h"

namespace acpca {

/// The options that decide a batch's files, as JSON (no times, no paths of
/// the output).
nlohmann::json datasetIdentity(const BatchRelightOptions& options);

/// Throws UserError naming the directory and the first setting that differs
/// when it holds a dataset.json of another batch. Reads only: every rank may
/// call it.
void refuseAnotherDataset(const std::string& directory, const nlohmann::json& identity);

/// Writes DIRECTORY/dataset.json (atomically).
void writeDatasetIdentity(const std::string& directory, const nlohmann::json& identity);

}  // namespace acpca
