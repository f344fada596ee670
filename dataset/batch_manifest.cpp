#include "dataset/batch_manifest.h"

#include <fcntl.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>

#include "core/error.h"

namespace acpca {

AppendOnlyFile::AppendOnlyFile(std::string path) : path_(std::move(path)) {
  fd_ = ::open(path_.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_APPEND | O_CLOEXEC, 0644);
  if (fd_ < 0)
    throw WriteError(concat(path_, ": cannot write the manifest: ", std::strerror(errno)));
}

AppendOnlyFile::~AppendOnlyFile() {
  if (fd_ >= 0) ::close(fd_);
}

void AppendOnlyFile::write(const std::string& text) {
  const ssize_t written = ::write(fd_, text.data(), text.size());
  if (written != static_cast<ssize_t>(text.size()))
    throw WriteError(concat(path_, ": cannot write the manifest: ",
                            written < 0 ? std::strerror(errno) : "the disk is full"));
}

BatchManifest::BatchManifest(std::string path, std::vector<std::string> columns)
    : file_(std::move(path)), columns_(std::move(columns)) {
  file_.write(Table(columns_).csvHeader());
}

void BatchManifest::append(std::vector<Table::Cell> row) {
  Table one(columns_);
  one.add(std::move(row));
  file_.write(one.csvRow(0));
}

}  // namespace acpca
