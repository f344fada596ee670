#pragma once
// Content hashes that identify files in a dataset's labels and frame headers
// (env_sha256, source_sha256): the same bytes, the same name, wherever the
// file lies.
#include <string>

namespace acpca {

/// SHA-256 of the file's bytes, 64 lowercase hex digits (what sha256sum
/// prints); UserError naming the file when it cannot be read.
std::string sha256OfFile(const std::string& path);

}  // namespace acpca
