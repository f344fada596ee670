#include "transport/dataset_slices.h"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <mutex>

#include "core/error.h"

namespace acpca {

namespace {

/// HDF5 calls from the slices' threads, one at a time.
std::mutex& libraryLock() {
  static std::mutex lock;
  return lock;
}

}  // namespace

DatasetSlices::DatasetSlices(hid_t file, const std::string& path, const std::string& name,
                             hid_t memType, const std::vector<hsize_t>& shape,
                             const std::string& ctx)
    : name_(name), ctx_(ctx), shape_(shape) {
  // datasetShape also checks that the file holds the bytes the shape declares.
  if (shape.empty() || h5::datasetShape(file, name, ctx) != shape)
    throw UserError(concat(ctx, ": dataset '", name, "' has the wrong size"));
  set_ = h5::Handle(h5::checkId(H5Dopen2(file, name.c_str(), H5P_DEFAULT), ctx, "open " + name),
                    H5Dclose);
  memType_ = h5::Handle(h5::checkId(H5Tcopy(memType), ctx, "type"), H5Tclose);
  entryBytes_ = H5Tget_size(memType);
  for (size_t d = 1; d < shape.size(); ++d) entryBytes_ *= shape[d];
  const h5::Handle fileType(h5::checkId(H5Dget_type(set_.get()), ctx, "type of " + name), H5Tclose);
  const h5::Handle creation(h5::checkId(H5Dget_create_plist(set_.get()), ctx, name), H5Pclose);
  // H5Dget_offset counts a user block; it is undefined unless the values are
  // one contiguous, allocated run inside the file.
  const haddr_t offset = H5Dget_offset(set_.get());
  const bool sameBytes = H5Tequal(fileType.get(), memType) > 0;
  if (!sameBytes || offset == HADDR_UNDEF || H5Pget_layout(creation.get()) != H5D_CONTIGUOUS ||
      H5Pget_external_count(creation.get()) != 0 || shape[0] * entryBytes_ == 0)
    return;
  const int fd = ::open(path.c_str(), O_RDONLY | O_CLOEXEC);
  struct stat st {};
  if (fd < 0) return;
  if (::fstat(fd, &st) != 0 ||
      double(offset) + double(shape[0]) * double(entryBytes_) > double(st.st_size)) {
    ::close(fd);
    return;
  }
  fd_ = fd;
  offset_ = static_cast<long long>(offset);
}

DatasetSlices::~DatasetSlices() {
  if (fd_ >= 0) ::close(fd_);
}

void DatasetSlices::read(long long first, long long count, void* out) const {
  ACPCA_CHECK(first >= 0 && count >= 0 && hsize_t(first + count) <= shape_[0], ctx_, ": slice of '",
              name_, "' out of range");
  if (count == 0) return;
  if (fd_ < 0) return readThroughLibrary(first, count, out);
  auto* bytes = static_cast<char*>(out);
  size_t left = static_cast<size_t>(count) * entryBytes_;
  off_t at = static_cast<off_t>(offset_ + first * static_cast<long long>(entryBytes_));
  while (left > 0) {
    const ssize_t got = ::pread(fd_, bytes, left, at);
    if (got < 0 && errno == EINTR) continue;
    if (got <= 0)
      throw UserError(concat(ctx_, ": reading dataset '", name_,
                             "' failed: ", got < 0 ? std::strerror(errno) : "the file ends early"));
    bytes += got, left -= static_cast<size_t>(got), at += got;
  }
}

void DatasetSlices::readThroughLibrary(long long first, long long count, void* out) const {
  const std::lock_guard<std::mutex> hold(libraryLock());
  std::vector<hsize_t> start(shape_.size(), 0), extent = shape_;
  start[0] = static_cast<hsize_t>(first);
  extent[0] = static_cast<hsize_t>(count);
  const h5::Handle fileSpace(h5::checkId(H5Dget_space(set_.get()), ctx_, name_), H5Sclose);
  h5::check(H5Sselect_hyperslab(fileSpace.get(), H5S_SELECT_SET, start.data(), nullptr,
                                extent.data(), nullptr),
            ctx_, "select in " + name_);
  const h5::Handle memSpace(
      h5::checkId(H5Screate_simple(int(extent.size()), extent.data(), nullptr), ctx_, name_),
      H5Sclose);
  h5::check(H5Dread(set_.get(), memType_.get(), memSpace.get(), fileSpace.get(), H5P_DEFAULT, out),
            ctx_, "read dataset '" + name_ + "'");
}

}  // namespace acpca
