#include "relight/batch_manifest.h"

#include <fcntl.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>

#include "core/error.h"

namespace acpca {

BatchManifest::BatchManifest(std::string path, std::vector<std::string> columns)
    : path_(std::move(path)), columns_(std::move(columns)) {
  fd_ = ::open(path_.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_APPEND | O_CLOEXEC, 0644);
  if (fd_ < 0)
    throw WriteError(concat(path_, ": cannot write the manifest: ", std::strerror(errno)));
  write(Table(columns_).csvHeader());
}

BatchManifest::~BatchManifest() {
  if (fd_ >= 0) ::close(fd_);
}

void BatchManifest::append(std::vector<Table::Cell> row) {
  Table one(columns_);
  one.add(std::move(row));
  write(one.csvRow(0));
}

void BatchManifest::write(const std::string& text) {
  // One write a row: a kill lands between rows, never inside one.
  const ssize_t written = ::write(fd_, text.data(), text.size());
  if (written != static_cast<ssize_t>(text.size()))
    throw WriteError(concat(path_, ": cannot write the manifest: ",
                            written < 0 ? std::strerror(errno) : "the disk is full"));
}

}  // namespace acpca
