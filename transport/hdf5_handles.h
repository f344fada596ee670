#pragma once
// Thin RAII and checked helpers over the HDF5 C API: every call's status is
// checked, and a failure becomes a UserError that names the file and the item.
#include <hdf5.h>

#include <cstdint>
#include <string>
#include <vector>

namespace acpca::h5 {

/// Owns one HDF5 identifier and closes it with the matching H5*close.
class Handle {
 public:
  using Closer = herr_t (*)(hid_t);
  Handle() = default;
  Handle(hid_t id, Closer closer) : id_(id), closer_(closer) {}
  Handle(const Handle&) = delete;
  Handle& operator=(const Handle&) = delete;
  Handle(Handle&& other) noexcept { *this = std::move(other); }
  Handle& operator=(Handle&& other) noexcept;
  ~Handle() { reset(); }
  hid_t get() const { return id_; }
  void reset();
  /// Closes now and returns the closer's status (reset() ignores it).
  herr_t close();

 private:
  hid_t id_ = -1;
  Closer closer_ = nullptr;
};

/// Silences HDF5's own error printing (we report errors ourselves). Idempotent.
void silenceLibraryErrors();
/// Throws UserError("<context>: <what>") when status < 0.
void check(herr_t status, const std::string& context, const std::string& what);
hid_t checkId(hid_t id, const std::string& context, const std::string& what);

/// The IEEE binary16 type, defined so that h5py reads it as numpy.float16
/// (HDF5 1.10 has no predefined half type).
Handle halfType();

/// Creates `path` (usually an AtomicOutput's temporary); errors name `output`,
/// the file the user asked for.
Handle createFile(const std::string& path, const std::string& output);
/// A dataset creation property list without object timestamps (files of equal
/// runs are equal byte for byte).
Handle datasetCreation();
/// Flushes and closes a file being written; throws a WriteError naming it when
/// the data did not reach the disk (disk full, directory removed).
void closeWrittenFile(Handle& file, const std::string& path);
Handle openFileReadOnly(const std::string& path);

bool hasAttribute(hid_t object, const std::string& name);
/// True when the file holds a link of that name at its root.
bool hasDataset(hid_t file, const std::string& name);
void writeAttribute(hid_t object, const std::string& name, long long value, const std::string& ctx);
void writeAttribute(hid_t object, const std::string& name, double value, const std::string& ctx);
void writeAttribute(hid_t object, const std::string& name, const std::string& value,
                    const std::string& ctx);
void writeAttribute(hid_t object, const std::string& name, const std::vector<double>& value,
                    const std::string& ctx);
long long readIntAttribute(hid_t object, const std::string& name, const std::string& ctx);
double readDoubleAttribute(hid_t object, const std::string& name, const std::string& ctx);
std::string readStringAttribute(hid_t object, const std::string& name, const std::string& ctx);
std::vector<double> readDoubleArrayAttribute(hid_t object, const std::string& name,
                                             const std::string& ctx);

/// Dimensions of a dataset (throws when missing).
std::vector<hsize_t> datasetShape(hid_t file, const std::string& name, const std::string& ctx);

/// Writes a whole small dataset of float/int32/uint8 values with the given shape.
void writeDataset(hid_t file, const std::string& name, const std::vector<hsize_t>& shape,
                  const float* data, const std::string& ctx);
void writeDataset(hid_t file, const std::string& name, const std::vector<hsize_t>& shape,
                  const std::int32_t* data, const std::string& ctx);
void writeDataset(hid_t file, const std::string& name, const std::vector<hsize_t>& shape,
                  const double* data, const std::string& ctx);
/// Writes / reads a whole dataset of any HDF5 type (memory and file type alike).
void writeTyped(hid_t file, const std::string& name, const std::vector<hsize_t>& shape, hid_t type,
                const void* data, const std::string& ctx);
void readTyped(hid_t file, const std::string& name, hid_t type, void* data, const std::string& ctx);
/// A one-dimensional dataset of a known size written in consecutive pieces:
/// contiguous and without timestamps, as writeDataset's, so a file written
/// piece by piece has the layout of one written whole.
class PiecewiseDataset {
 public:
  PiecewiseDataset() = default;
  PiecewiseDataset(hid_t file, const std::string& name, hid_t fileType, hsize_t size,
                   const std::string& ctx);
  /// Writes count values of memType (converted to the file's type) after the
  /// last piece; never past the size.
  void append(hid_t memType, const void* data, hsize_t count);
  hsize_t written() const { return written_; }
  hsize_t size() const { return size_; }

 private:
  Handle set_;
  std::string name_, ctx_;
  hsize_t size_ = 0, written_ = 0;
};

/// Reads a whole dataset whose shape the caller has already validated.
void readDataset(hid_t file, const std::string& name, float* data, const std::string& ctx);
void readDataset(hid_t file, const std::string& name, std::int32_t* data, const std::string& ctx);

}  // namespace acpca::h5
