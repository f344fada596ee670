#pragma once
// Slices of a large dataset (runs of its first index) read from many threads at once (a model's
// bases and coefficients, cluster by cluster, as the relighter packs them).
// HDF5 (Debian's build) serves one thread at a time, so where the dataset's
// values lie in the file contiguous and in exactly the memory type's bytes,
// they are read with pread from the file itself, never through HDF5; other
// layouts (chunked, another byte order, another type) go through HDF5 under
// a lock.
#include <hdf5.h>

#include <string>
#include <vector>

#include "transport/hdf5_handles.h"

namespace acpca {

class DatasetSlices {
 public:
  /// Dataset `name` of `file` (opened from `path`), which must have exactly
  /// `shape`; read as `memType`. UserError naming ctx otherwise.
  DatasetSlices(hid_t file, const std::string& path, const std::string& name, hid_t memType,
                const std::vector<hsize_t>& shape, const std::string& ctx);
  ~DatasetSlices();
  DatasetSlices(const DatasetSlices&) = delete;
  DatasetSlices& operator=(const DatasetSlices&) = delete;

  /// Entries [first, first + count) of the first index into out (count x
  /// the other extents x the memory type's size bytes); from any thread.
  /// UserError naming the dataset on a failed read.
  void read(long long first, long long count, void* out) const;
  /// Whether slices are read straight from the file.
  bool direct() const { return fd_ >= 0; }

 private:
  void readThroughLibrary(long long first, long long count, void* out) const;

  h5::Handle set_, memType_;
  std::string name_, ctx_;
  std::vector<hsize_t> shape_;
  size_t entryBytes_ = 0;  ///< one entry of the first index: the rest of the shape
  int fd_ = -1;            ///< the file, opened again for pread; -1 when not direct
  long long offset_ = 0;   ///< the values' first byte in the file
};

}  // namespace acpca
