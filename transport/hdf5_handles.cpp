#include "transport/hdf5_handles.h"

#include <algorithm>
#include <cstdint>
#include <fstream>
#include <mutex>

#include "core/error.h"
#include "core/half.h"

namespace acpca::h5 {

Handle& Handle::operator=(Handle&& other) noexcept {
  if (this != &other) {
    reset();
    id_ = other.id_;
    closer_ = other.closer_;
    other.id_ = -1;
  }
  return *this;
}

void Handle::reset() {
  close();
}

herr_t Handle::close() {
  herr_t status = 0;
  if (id_ >= 0 && closer_) status = closer_(id_);
  id_ = -1;
  return status;
}

namespace {
// HDF5's own exit handler closes files left open; after a failed write (full
// disk) libhdf5 1.10 crashes doing so. Every file is closed explicitly, so the
// handler is not needed; this must run before any other HDF5 call.
[[maybe_unused]] const herr_t kNoExitHandler = H5dont_atexit();
}  // namespace

void silenceLibraryErrors() {
  static std::once_flag once;
  std::call_once(once, [] { H5Eset_auto2(H5E_DEFAULT, nullptr, nullptr); });
}

void check(herr_t status, const std::string& context, const std::string& what) {
  if (status < 0) throw UserError(concat(context, ": ", what));
}

hid_t checkId(hid_t id, const std::string& context, const std::string& what) {
  if (id < 0) throw UserError(concat(context, ": ", what));
  return id;
}

Handle halfType() {
  Handle type(H5Tcopy(H5T_IEEE_F32LE), H5Tclose);
  const hid_t t = type.get();
  // Sign bit 15, exponent bits 10..14, mantissa bits 0..9, bias 15: binary16.
  check(H5Tset_fields(t, 15, 10, 5, 0, 10), "HDF5", "defining the half type");
  check(H5Tset_precision(t, 16), "HDF5", "defining the half type");
  check(H5Tset_size(t, 2), "HDF5", "defining the half type");
  check(H5Tset_ebias(t, 15), "HDF5", "defining the half type");
  return type;
}

Handle createFile(const std::string& path, const std::string& output) {
  silenceLibraryErrors();
  // The 1.10 file format: every piece of metadata (superblock, object headers,
  // chunk indices) carries a checksum that HDF5 verifies before parsing it, so a
  // corrupt or hostile file is refused instead of reaching the library's parsers
  // (which fuzzing showed can crash on damaged unchecked metadata).
  Handle access(H5Pcreate(H5P_FILE_ACCESS), H5Pclose);
  check(H5Pset_libver_bounds(access.get(), H5F_LIBVER_V110, H5F_LIBVER_V110), output,
        "file format bounds");
  // No object timestamps (HDF5 keeps them by default): equal runs write equal bytes.
  Handle create(H5Pcreate(H5P_FILE_CREATE), H5Pclose);
  check(H5Pset_obj_track_times(create.get(), false), output, "object timestamps");
  return Handle(checkId(H5Fcreate(path.c_str(), H5F_ACC_TRUNC, create.get(), access.get()), output,
                        "cannot create the file (is the directory writable?)"),
                H5Fclose);
}

Handle datasetCreation() {
  Handle create(H5Pcreate(H5P_DATASET_CREATE), H5Pclose);
  check(H5Pset_obj_track_times(create.get(), false), "HDF5", "object timestamps");
  return create;
}

void closeWrittenFile(Handle& file, const std::string& path) {
  const bool flushed = H5Fflush(file.get(), H5F_SCOPE_GLOBAL) >= 0;
  const bool closed = file.close() >= 0;
  if (!flushed || !closed)
    throw WriteError(
        concat(path, ": cannot write the file (disk full, or its directory removed?)"));
}

Handle openFileReadOnly(const std::string& path) {
  silenceLibraryErrors();
  // Byte 8 of the superblock is its version: 2 and up have checksums (see createFile).
  char head[9] = {};
  std::ifstream(path, std::ios::binary).read(head, sizeof head);
  if (std::string(head, 8) != "\x89HDF\r\n\x1a\n" || H5Fis_hdf5(path.c_str()) <= 0)
    throw UserError(concat(path, ": not an HDF5 file (missing, unreadable, truncated or foreign)"));
  if (head[8] < 2)
    throw UserError(concat(path, ": HDF5 file without metadata checksums (superblock version ",
                           int(head[8]),
                           "): not written by this version of adaptive-cpca; write it again"));
  return Handle(
      checkId(H5Fopen(path.c_str(), H5F_ACC_RDONLY, H5P_DEFAULT), path, "cannot open the file"),
      H5Fclose);
}

bool hasAttribute(hid_t object, const std::string& name) {
  return H5Aexists(object, name.c_str()) > 0;
}

bool hasDataset(hid_t file, const std::string& name) {
  return H5Lexists(file, name.c_str(), H5P_DEFAULT) > 0;
}

namespace {

void writeScalarAttribute(hid_t object, const std::string& name, hid_t type, const void* value,
                          const std::string& ctx) {
  Handle space(H5Screate(H5S_SCALAR), H5Sclose);
  if (hasAttribute(object, name)) check(H5Adelete(object, name.c_str()), ctx, "replacing " + name);
  Handle attr(checkId(H5Acreate2(object, name.c_str(), type, space.get(), H5P_DEFAULT, H5P_DEFAULT),
                      ctx, "cannot write attribute " + name),
              H5Aclose);
  check(H5Awrite(attr.get(), type, value), ctx, "cannot write attribute " + name);
}

Handle openAttribute(hid_t object, const std::string& name, const std::string& ctx) {
  if (!hasAttribute(object, name)) throw UserError(concat(ctx, ": missing attribute '", name, "'"));
  return Handle(checkId(H5Aopen(object, name.c_str(), H5P_DEFAULT), ctx, "cannot open " + name),
                H5Aclose);
}

hssize_t attributeElements(hid_t attr) {
  Handle space(H5Aget_space(attr), H5Sclose);
  return H5Sget_simple_extent_npoints(space.get());
}

template <typename T>
T readScalarAttribute(hid_t object, const std::string& name, hid_t memType,
                      const std::string& ctx) {
  Handle attr = openAttribute(object, name, ctx);
  if (attributeElements(attr.get()) != 1)
    throw UserError(concat(ctx, ": attribute '", name, "' is not a single value"));
  Handle fileType(H5Aget_type(attr.get()), H5Tclose);
  if (H5Tget_class(fileType.get()) == H5T_STRING)
    throw UserError(concat(ctx, ": attribute '", name, "' is text, expected a number"));
  T value{};
  check(H5Aread(attr.get(), memType, &value), ctx, "cannot read attribute " + name);
  return value;
}

Handle openDataset(hid_t file, const std::string& name, const std::string& ctx) {
  if (H5Lexists(file, name.c_str(), H5P_DEFAULT) <= 0)
    throw UserError(concat(ctx, ": missing dataset '", name, "'"));
  return Handle(checkId(H5Dopen2(file, name.c_str(), H5P_DEFAULT), ctx, "cannot open " + name),
                H5Dclose);
}

void writeWhole(hid_t file, const std::string& name, const std::vector<hsize_t>& shape, hid_t type,
                const void* data, const std::string& ctx) {
  Handle space(H5Screate_simple(static_cast<int>(shape.size()), shape.data(), nullptr), H5Sclose);
  const Handle create = datasetCreation();
  Handle set(checkId(H5Dcreate2(file, name.c_str(), type, space.get(), H5P_DEFAULT, create.get(),
                                H5P_DEFAULT),
                     ctx, "cannot create dataset " + name),
             H5Dclose);
  hsize_t count = 1;
  for (hsize_t d : shape) count *= d;
  if (count > 0)
    if (H5Dwrite(set.get(), type, H5S_ALL, H5S_ALL, H5P_DEFAULT, data) < 0)
      throw WriteError(
          concat(ctx, ": cannot write dataset ", name, " (disk full, or its directory removed?)"));
}

void readWhole(hid_t file, const std::string& name, hid_t type, void* data,
               const std::string& ctx) {
  Handle set = openDataset(file, name, ctx);
  Handle space(H5Dget_space(set.get()), H5Sclose);
  const hssize_t count = H5Sget_simple_extent_npoints(space.get());
  if (count == 0) return;
  const std::string failure = "cannot read dataset " + name + " (corrupt or truncated?)";
  if (H5Tequal(type, H5T_NATIVE_FLOAT) > 0) {
    // HDF5 converts half to float bit by bit in software (about 20 ns a value,
    // seconds for a large model's bases); read the halves as stored and
    // convert them with the CPU's instructions instead: the same floats.
    const Handle fileType(H5Dget_type(set.get()), H5Tclose);
    const Handle half = halfType();
    if (count > 0 && H5Tequal(fileType.get(), half.get()) > 0) {
      std::vector<std::uint16_t> stored(static_cast<size_t>(count));
      check(H5Dread(set.get(), half.get(), H5S_ALL, H5S_ALL, H5P_DEFAULT, stored.data()), ctx,
            failure);
      halfToFloat(stored.data(), static_cast<float*>(data), stored.size());
      return;
    }
  }
  check(H5Dread(set.get(), type, H5S_ALL, H5S_ALL, H5P_DEFAULT, data), ctx, failure);
}

}  // namespace

PiecewiseDataset::PiecewiseDataset(hid_t file, const std::string& name, hid_t fileType,
                                   hsize_t size, const std::string& ctx)
    : name_(name), ctx_(ctx), size_(size) {
  Handle space(H5Screate_simple(1, &size, nullptr), H5Sclose);
  const Handle creation = datasetCreation();
  set_ = Handle(checkId(H5Dcreate2(file, name.c_str(), fileType, space.get(), H5P_DEFAULT,
                                   creation.get(), H5P_DEFAULT),
                        ctx, "cannot create dataset " + name),
                H5Dclose);
}

void PiecewiseDataset::append(hid_t memType, const void* data, hsize_t count) {
  if (count == 0) return;
  ACPCA_CHECK(written_ + count <= size_, name_, ": ", written_ + count, " values written into ",
              size_);
  Handle fileSpace(H5Dget_space(set_.get()), H5Sclose);
  check(H5Sselect_hyperslab(fileSpace.get(), H5S_SELECT_SET, &written_, nullptr, &count, nullptr),
        ctx_, "selection in " + name_);
  Handle memSpace(H5Screate_simple(1, &count, nullptr), H5Sclose);
  if (H5Dwrite(set_.get(), memType, memSpace.get(), fileSpace.get(), H5P_DEFAULT, data) < 0)
    throw WriteError(
        concat(ctx_, ": cannot write dataset ", name_, " (disk full, or its directory removed?)"));
  written_ += count;
}

void writeAttribute(hid_t object, const std::string& name, long long value,
                    const std::string& ctx) {
  writeScalarAttribute(object, name, H5T_NATIVE_LLONG, &value, ctx);
}

void writeAttribute(hid_t object, const std::string& name, double value, const std::string& ctx) {
  writeScalarAttribute(object, name, H5T_NATIVE_DOUBLE, &value, ctx);
}

void writeAttribute(hid_t object, const std::string& name, const std::string& value,
                    const std::string& ctx) {
  Handle type(H5Tcopy(H5T_C_S1), H5Tclose);
  check(H5Tset_size(type.get(), std::max<size_t>(1, value.size())), ctx, "string type");
  check(H5Tset_cset(type.get(), H5T_CSET_UTF8), ctx, "string type");
  std::string padded = value.empty() ? std::string(1, '\0') : value;
  writeScalarAttribute(object, name, type.get(), padded.data(), ctx);
}

void writeAttribute(hid_t object, const std::string& name, const std::vector<double>& value,
                    const std::string& ctx) {
  const hsize_t n = value.size();
  Handle space(H5Screate_simple(1, &n, nullptr), H5Sclose);
  Handle attr(checkId(H5Acreate2(object, name.c_str(), H5T_NATIVE_DOUBLE, space.get(), H5P_DEFAULT,
                                 H5P_DEFAULT),
                      ctx, "cannot write attribute " + name),
              H5Aclose);
  check(H5Awrite(attr.get(), H5T_NATIVE_DOUBLE, value.data()), ctx, "attribute " + name);
}

long long readIntAttribute(hid_t object, const std::string& name, const std::string& ctx) {
  return readScalarAttribute<long long>(object, name, H5T_NATIVE_LLONG, ctx);
}

double readDoubleAttribute(hid_t object, const std::string& name, const std::string& ctx) {
  return readScalarAttribute<double>(object, name, H5T_NATIVE_DOUBLE, ctx);
}

std::string readStringAttribute(hid_t object, const std::string& name, const std::string& ctx) {
  Handle attr = openAttribute(object, name, ctx);
  Handle type(H5Aget_type(attr.get()), H5Tclose);
  if (H5Tget_class(type.get()) != H5T_STRING || H5Tis_variable_str(type.get()) > 0)
    throw UserError(concat(ctx, ": attribute '", name, "' is not fixed-length text"));
  const size_t size = H5Tget_size(type.get());
  if (size > (1u << 20)) throw UserError(concat(ctx, ": attribute '", name, "' is too long"));
  std::string value(size, '\0');
  check(H5Aread(attr.get(), type.get(), value.data()), ctx, "cannot read attribute " + name);
  value.resize(value.find('\0') == std::string::npos ? size : value.find('\0'));
  return value;
}

std::vector<double> readDoubleArrayAttribute(hid_t object, const std::string& name,
                                             const std::string& ctx) {
  Handle attr = openAttribute(object, name, ctx);
  const hssize_t n = attributeElements(attr.get());
  if (n < 0 || n > 4096) throw UserError(concat(ctx, ": attribute '", name, "' has a bad size"));
  std::vector<double> values(n);
  check(H5Aread(attr.get(), H5T_NATIVE_DOUBLE, values.data()), ctx, "attribute " + name);
  return values;
}

std::vector<hsize_t> datasetShape(hid_t file, const std::string& name, const std::string& ctx) {
  Handle set = openDataset(file, name, ctx);
  Handle space(H5Dget_space(set.get()), H5Sclose);
  const int rank = H5Sget_simple_extent_ndims(space.get());
  if (rank < 0 || rank > 8) throw UserError(concat(ctx, ": dataset '", name, "' has a bad rank"));
  std::vector<hsize_t> dims(rank);
  H5Sget_simple_extent_dims(space.get(), dims.data(), nullptr);
  // Our datasets are stored whole and uncompressed: a shape whose bytes the
  // file does not hold is a corrupt or hostile header, refused before a caller
  // allocates for it (a declared 10^12 values must not become a 4 TB vector).
  Handle type(H5Dget_type(set.get()), H5Tclose);
  const double declared = double(H5Sget_simple_extent_npoints(space.get())) *
                          double(type.get() >= 0 ? H5Tget_size(type.get()) : 0);
  hsize_t fileBytes = 0;
  H5Fget_filesize(file, &fileBytes);
  const double stored = double(H5Dget_storage_size(set.get()));
  if (declared > stored || stored > double(fileBytes))
    throw UserError(concat(ctx, ": dataset '", name, "' declares ", declared,
                           " bytes but the file holds ", std::min(stored, double(fileBytes)),
                           " (truncated or corrupt)"));
  return dims;
}

void writeTyped(hid_t file, const std::string& name, const std::vector<hsize_t>& shape, hid_t type,
                const void* data, const std::string& ctx) {
  writeWhole(file, name, shape, type, data, ctx);
}
void readTyped(hid_t file, const std::string& name, hid_t type, void* data,
               const std::string& ctx) {
  readWhole(file, name, type, data, ctx);
}
void writeDataset(hid_t file, const std::string& name, const std::vector<hsize_t>& shape,
                  const float* data, const std::string& ctx) {
  writeWhole(file, name, shape, H5T_NATIVE_FLOAT, data, ctx);
}
void writeDataset(hid_t file, const std::string& name, const std::vector<hsize_t>& shape,
                  const std::int32_t* data, const std::string& ctx) {
  writeWhole(file, name, shape, H5T_NATIVE_INT32, data, ctx);
}
void writeDataset(hid_t file, const std::string& name, const std::vector<hsize_t>& shape,
                  const double* data, const std::string& ctx) {
  writeWhole(file, name, shape, H5T_NATIVE_DOUBLE, data, ctx);
}
void readDataset(hid_t file, const std::string& name, float* data, const std::string& ctx) {
  readWhole(file, name, H5T_NATIVE_FLOAT, data, ctx);
}
void readDataset(hid_t file, const std::string& name, std::int32_t* data, const std::string& ctx) {
  readWhole(file, name, H5T_NATIVE_INT32, data, ctx);
}

}  // namespace acpca::h5
