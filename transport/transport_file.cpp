#include "transport/transport_file.h"

#include <algorithm>
#include <cmath>
#include <filesystem>

#include "core/error.h"
#include "core/half.h"
#include "transport/cube_lattice.h"
#include "transport/file_summary.h"
#include "transport/image_header.h"

namespace acpca {

Precision parsePrecision(const std::string& text) {
  return kPrecisionNames.parse(text);
}

const char* precisionName(Precision p) {
  return kPrecisionNames.name(p);
}

void TransportHeader::validate(const std::string& context) const {
  if (isLightSet()) {
    lights.validate(context);
    validateImageSize(camera.size, context);
    if (cubemapResolution != 0)
      throw UserError(concat(context, ": a light set's transport has no cube map"));
  } else {
    camera.validate();
    if (cubemapResolution < 1 || cubemapResolution > CubeLattice::kMaxResolution)
      throw UserError(
          concat(context, ": cube-map resolution ", cubemapResolution, " out of range"));
  }
  if (samplesPerPixel < 1 || texelRays < 1)
    throw UserError(concat(context, ": samples per pixel and rays per texel must be >= 1"));
  if (channels != 1 && channels != 3)
    throw UserError(concat(context, ": ", channels, " channels per row, not 1 or 3"));
  if (bounces < 0 || indirectSamples < 0 || !(indirectCacheCell >= 0) ||
      (bounces > 0 && indirectSamples < 1))
    throw UserError(concat(context, ": bounces ", bounces, " with ", indirectSamples,
                           " indirect samples and cache cell ", indirectCacheCell));
  const long long n = rows();
  if (n > camera.size.pixels())
    throw UserError(concat(context, ": ", n, " rows for a ", camera.size.width, "x",
                           camera.size.height, " image"));
  if (static_cast<long long>(albedo.size()) != 3 * n ||
      static_cast<long long>(coverage.size()) != n ||
      (!normals.empty() && static_cast<long long>(normals.size()) != 3 * n) ||
      (!positions.empty() && static_cast<long long>(positions.size()) != 3 * n) ||
      (!objects.empty() && static_cast<long long>(objects.size()) != n))
    throw UserError(concat(context, ": per-pixel arrays do not match the ", n, " rows"));
  for (std::int32_t id : objects)
    if (id < 0 || id >= static_cast<long long>(objectNames.size()))
      throw UserError(concat(context, ": object id ", id, " is not one of the ", objectNames.size(),
                             " objects"));
  for (float x : positions)
    if (!std::isfinite(x)) throw UserError(concat(context, ": pixel positions must be finite"));
  for (long long i = 0; i < n; ++i) {
    if (pixels[i] < 0 || pixels[i] >= camera.size.pixels() || (i > 0 && pixels[i] <= pixels[i - 1]))
      throw UserError(concat(context, ": pixel index of row ", i, " is out of order or range"));
  }
  for (float a : albedo)
    if (!std::isfinite(a) || a < 0)
      throw UserError(concat(context, ": albedo must be finite, >= 0"));
  for (float c : coverage)
    if (!(c >= 0 && c <= 1)) throw UserError(concat(context, ": coverage must be in [0, 1]"));
  lamps.validate(n, context);
}

ColumnGeometry columnGeometry(const TransportHeader& header) {
  if (header.isLightSet()) return {header.lights.directions, header.lights.solidAngles};
  const CubeLattice lattice(header.cubemapResolution);
  ColumnGeometry columns{{}, lattice.solidAngles()};
  for (int j = 0; j < lattice.size(); ++j) columns.directions.push_back(lattice.direction(j));
  return columns;
}

namespace {

constexpr const char* kRowsDataset = "transport";

// About 1 MiB chunks: large enough for fast streaming, small enough to cache.
hsize_t rowsPerChunk(int rowLength, Precision p) {
  const hsize_t rowBytes = static_cast<hsize_t>(rowLength) * (p == Precision::F16 ? 2 : 4);
  return std::clamp<hsize_t>((1u << 20) / rowBytes, 1, 4096);
}

}  // namespace

TransportWriter::TransportWriter(const std::string& path, const TransportHeader& header)
    : output_(path), header_(header) {
  header_.validate(path);
  ACPCA_CHECK(header_.hasNormals() || header_.isLightSet(),
              "a transport of a scene keeps every row's normal");
  const std::string& ctx = path;
  file_ = h5::createFile(output_.tempPath(), path);
  const hid_t f = file_.get();
  h5::writeAttribute(f, "format", std::string(kTransportFormat), ctx);
  h5::writeAttribute(f, "version", static_cast<long long>(kTransportVersion), ctx);
  h5::writeAttribute(f, "spp", static_cast<long long>(header.samplesPerPixel), ctx);
  h5::writeAttribute(f, "texel_rays", static_cast<long long>(header.texelRays), ctx);
  h5::writeAttribute(f, "precision", std::string(precisionName(header.precision)), ctx);
  writeImageHeader(f, header, ctx);
  const hsize_t n = header.rows();

  // The columns' directions and solid angles (texels, or a light set's
  // lights and cells), so that readers (h5py) need not re-derive them:
  // B = albedo * (T @ (radiance * solid_angle)).
  const ColumnGeometry columns = columnGeometry(header);
  std::vector<double> directions;
  for (const Vec3& d : columns.directions)
    directions.insert(directions.end(), {d.x(), d.y(), d.z()});
  const hsize_t l = header.latticeSize();
  h5::writeDataset(f, "lattice_solid_angle", {l}, columns.solidAngles.data(), ctx);
  h5::writeDataset(f, "lattice_direction", {l, 3}, directions.data(), ctx);
  const hsize_t width = header.rowLength();
  const hsize_t dims[2] = {n, width}, maxDims[2] = {H5S_UNLIMITED, width};
  const hsize_t chunk[2] = {rowsPerChunk(header.rowLength(), header.precision), width};
  h5::Handle space(H5Screate_simple(2, dims, maxDims), H5Sclose);
  h5::Handle create = h5::datasetCreation();
  h5::check(H5Pset_chunk(create.get(), 2, chunk), ctx, "chunk layout");
  h5::Handle access(H5Pcreate(H5P_DATASET_ACCESS), H5Pclose);
  h5::check(H5Pset_chunk_cache(access.get(), 521, 32u << 20, 1.0), ctx, "chunk cache");
  if (header.precision == Precision::F16) halfType_ = h5::halfType();
  const hid_t type = header.precision == Precision::F16 ? halfType_.get() : H5T_IEEE_F32LE;
  rows_ = h5::Handle(h5::checkId(H5Dcreate2(f, kRowsDataset, type, space.get(), H5P_DEFAULT,
                                            create.get(), access.get()),
                                 ctx, "cannot create the transport dataset"),
                     H5Dclose);
}

TransportWriter::~TransportWriter() = default;

void TransportWriter::writeRows(long long firstRow, long long count, const float* rows) {
  ACPCA_CHECK(firstRow == nextRow_ && count >= 0 && firstRow + count <= header_.rows(), "rows ",
              firstRow, "+", count, " after ", nextRow_);
  if (count == 0) return;
  const hsize_t l = header_.rowLength();
  const hsize_t start[2] = {static_cast<hsize_t>(firstRow), 0}, size[2] = {(hsize_t)count, l};
  h5::Handle fileSpace(H5Dget_space(rows_.get()), H5Sclose);
  h5::check(H5Sselect_hyperslab(fileSpace.get(), H5S_SELECT_SET, start, nullptr, size, nullptr),
            output_.finalPath(), "row selection");
  h5::Handle memSpace(H5Screate_simple(2, size, nullptr), H5Sclose);
  const size_t values = static_cast<size_t>(count) * l;
  herr_t status;
  if (header_.precision == Precision::F16) {
    halfBuffer_.resize(values);
    floatToHalf(rows, halfBuffer_.data(), values);
    status = H5Dwrite(rows_.get(), halfType_.get(), memSpace.get(), fileSpace.get(), H5P_DEFAULT,
                      halfBuffer_.data());
    bytesWritten_ += values * 2;
  } else {
    status =
        H5Dwrite(rows_.get(), H5T_NATIVE_FLOAT, memSpace.get(), fileSpace.get(), H5P_DEFAULT, rows);
    bytesWritten_ += values * 4;
  }
  if (status < 0)
    throw WriteError(
        concat(output_.finalPath(),
               ": cannot write transport rows (disk full, or its directory removed?)"));
  nextRow_ += count;
}

void TransportWriter::finish() {
  ACPCA_CHECK(nextRow_ == header_.rows(), "wrote ", nextRow_, " of ", header_.rows(), " rows");
  rows_.reset();
  // The completion marker is written last: a file without it is never read.
  h5::writeAttribute(file_.get(), "complete", 1LL, output_.finalPath());
  h5::closeWrittenFile(file_, output_.finalPath());
  output_.commit();
}

namespace {

/// The transport file at `path`, its format, version and completeness checked.
h5::Handle openTransportFile(const std::string& path) {
  const std::string& ctx = path;
  h5::Handle file = h5::openFileReadOnly(path);
  const hid_t f = file.get();
  if (!h5::hasAttribute(f, "format") ||
      h5::readStringAttribute(f, "format", ctx) != kTransportFormat)
    throw UserError(concat(ctx, ": not an adaptive-cpca transport file"));
  const long long version = h5::readIntAttribute(f, "version", ctx);
  if (version < kOldestTransportVersion || version > kTransportVersion)
    throw UserError(concat(ctx, ": transport format version ", version, ", this build reads ",
                           kOldestTransportVersion, " to ", kTransportVersion));
  if (!h5::hasAttribute(f, "complete") || h5::readIntAttribute(f, "complete", ctx) != 1)
    throw UserError(concat(ctx, ": the file is incomplete (its precompute did not finish)"));
  return file;
}

/// The attributes only transports have, and the rows' shape (`rows` of them).
void readTransportAttributes(hid_t f, const std::string& ctx, long long rows, TransportHeader& h) {
  h.samplesPerPixel = static_cast<int>(h5::readIntAttribute(f, "spp", ctx));
  h.texelRays = static_cast<int>(h5::readIntAttribute(f, "texel_rays", ctx));
  const std::string precision = h5::readStringAttribute(f, "precision", ctx);
  if (precision != "f16" && precision != "f32")
    throw UserError(concat(ctx, ": attribute 'precision' is '", precision, "', not f16 or f32"));
  h.precision = parsePrecision(precision);
  if (h5::datasetShape(f, kRowsDataset, ctx) !=
      std::vector<hsize_t>{hsize_t(rows), hsize_t(h.rowLength())})
    throw UserError(concat(ctx, ": dataset '", kRowsDataset, "' has the wrong shape"));
}

long long fileBytesOf(const std::string& path) {
  std::error_code ec;
  const auto size = std::filesystem::file_size(path, ec);
  return ec ? -1 : static_cast<long long>(size);
}

}  // namespace

PixelDatasets PixelDatasets::of(const TransportHeader& h) {
  return {h.rows(),         h.hasNormals(),           h.hasPositions(), h.hasObjects(),
          !h.lamps.empty(), !h.lamps.tangent.empty(), h.lamps.materials};
}

TransportSummary readTransportSummary(const std::string& path) {
  const h5::Handle file = openTransportFile(path);
  TransportSummary s;
  s.header = readImageHeaderAttributes(file.get(), true, path, s.pixels);
  readTransportAttributes(file.get(), path, s.pixels.rows, s.header);
  s.fileBytes = fileBytesOf(path);
  return s;
}

TransportReader::TransportReader(const std::string& path) : path_(path) {
  const std::string& ctx = path;
  file_ = openTransportFile(path);
  const hid_t f = file_.get();
  header_ = readImageHeader(f, true, ctx);
  auto& h = header_;
  readTransportAttributes(f, ctx, h.rows(), h);
  h.validate(ctx);

  rows_ = h5::Handle(h5::checkId(H5Dopen2(f, kRowsDataset, H5P_DEFAULT), ctx, "transport rows"),
                     H5Dclose);
  h5::Handle type(H5Dget_type(rows_.get()), H5Tclose);
  const size_t size = H5Tget_size(type.get());
  if (H5Tget_class(type.get()) != H5T_FLOAT || size != (h.precision == Precision::F16 ? 2u : 4u))
    throw UserError(concat(ctx, ": transport rows are not ", precisionName(h.precision)));
}

void TransportReader::readRows(long long first, long long count, float* out) const {
  ACPCA_CHECK(first >= 0 && count >= 0 && first + count <= rows(), "rows ", first, "+", count);
  if (count == 0) return;
  const hsize_t l = rowLength();
  const hsize_t start[2] = {static_cast<hsize_t>(first), 0}, size[2] = {(hsize_t)count, l};
  h5::Handle fileSpace(H5Dget_space(rows_.get()), H5Sclose);
  h5::check(H5Sselect_hyperslab(fileSpace.get(), H5S_SELECT_SET, start, nullptr, size, nullptr),
            path_, "row selection");
  h5::Handle memSpace(H5Screate_simple(2, size, nullptr), H5Sclose);
  herr_t status;
  const size_t values = static_cast<size_t>(count) * l;
  if (header_.precision == Precision::F16) {
    halfBuffer_.resize(values);
    h5::Handle type(H5Dget_type(rows_.get()), H5Tclose);  // read raw: no soft conversion
    status = H5Dread(rows_.get(), type.get(), memSpace.get(), fileSpace.get(), H5P_DEFAULT,
                     halfBuffer_.data());
    if (status >= 0) halfToFloat(halfBuffer_.data(), out, values);
  } else {
    status =
        H5Dread(rows_.get(), H5T_NATIVE_FLOAT, memSpace.get(), fileSpace.get(), H5P_DEFAULT, out);
  }
  h5::check(status, path_,
            concat("cannot read transport rows ", first, "..", first + count,
                   " (truncated or corrupt file?)"));
  for (size_t i = 0; i < values; ++i)
    if (!std::isfinite(out[i]))
      throw UserError(concat(path_, ": non-finite transport value in row ", first + i / l));
}

long long TransportReader::fileBytes() const {
  return fileBytesOf(path_);
}

}  // namespace acpca
