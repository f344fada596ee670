// Structured fuzzing of the two HDF5 readers: a valid small transport or model
// file is written by our own writers, then edited as the fuzzer says: header
// attributes set to any value (wrong format, version, sizes), datasets deleted,
// replaced by values of the fuzzer's choosing (NaN included) or declared with
// absurd dimensions that were never written. The readers must refuse with a
// UserError before allocating for a shape the file does not hold, or accept a
// file whose relight is finite.
#include <fuzzer/FuzzedDataProvider.h>
#include <hdf5.h>

#include "cluster/quantization.h"
#include "fuzz/fuzz_support.h"
#include "lighting/environment.h"
#include "lighting/lighting.h"
#include "model/model.h"
#include "model/model_file.h"
#include "relight/dense_relight.h"
#include "relight/model_relighter.h"
#include "transport/hdf5_handles.h"
#include "transport/transport_file.h"

namespace acpca {
namespace {

const char* const kTransportInts[] = {"version", "complete", "width",      "height",
                                      "cubemap", "spp",      "texel_rays", "occupied_pixels"};
const char* const kTransportStrings[] = {"format", "precision", "scene"};
const char* const kTransportSets[] = {"transport", "pixels", "albedo", "coverage", "normal"};
const char* const kModelInts[] = {"version",      "complete", "width",
                                  "height",       "cubemap",  "occupied_pixels",
                                  "global_bases", "clusters", "has_mean"};
const char* const kModelStrings[] = {"format", "coeffs", "bases", "method"};
const char* const kModelSets[] = {"pixels",
                                  "albedo",
                                  "coverage",
                                  "global_basis",
                                  "cluster_rows",
                                  "cluster_row_offsets",
                                  "cluster_rank",
                                  "cluster_basis_offsets",
                                  "bases",
                                  "means",
                                  "coefficient_offsets",
                                  "coefficient_scale",
                                  "coefficients"};

long long anyInteger(FuzzedDataProvider& in) {
  switch (in.ConsumeIntegralInRange(0, 3)) {
    case 0:
      return in.ConsumeIntegralInRange<long long>(-2, 8);
    case 1:
      return in.ConsumeIntegralInRange<long long>(0, 1 << 20);
    case 2:
      return in.ConsumeIntegral<long long>();
    default:
      return (1LL << in.ConsumeIntegralInRange(20, 62)) - in.ConsumeIntegralInRange(0, 1);
  }
}

float anyFloat(FuzzedDataProvider& in) {
  switch (in.ConsumeIntegralInRange(0, 4)) {
    case 0:
      return std::numeric_limits<float>::quiet_NaN();
    case 1:
      return std::numeric_limits<float>::infinity();
    case 2:
      return in.ConsumeFloatingPointInRange(-2.0f, 2.0f);
    default:
      return in.ConsumeFloatingPoint<float>();
  }
}

void replaceDataset(hid_t file, const char* name, FuzzedDataProvider& in) {
  if (H5Lexists(file, name, H5P_DEFAULT) > 0) H5Ldelete(file, name, H5P_DEFAULT);
  const int action = in.ConsumeIntegralInRange(0, 2);
  if (action == 0) return;  // missing
  const int rank = in.ConsumeIntegralInRange(1, 2);
  hsize_t dims[2];
  for (int d = 0; d < rank; ++d)
    dims[d] = static_cast<hsize_t>(std::max<long long>(0, anyInteger(in)) % (1LL << 40));
  h5::Handle space(H5Screate_simple(rank, dims, nullptr), H5Sclose);
  if (space.get() < 0) return;
  const hid_t type = in.ConsumeBool() ? H5T_NATIVE_FLOAT : H5T_NATIVE_INT64;
  if (action == 1) {  // declared, chunked, never written: the file holds none of it
    h5::Handle create(H5Pcreate(H5P_DATASET_CREATE), H5Pclose);
    hsize_t chunk[2] = {1, 1};
    H5Pset_chunk(create.get(), rank, chunk);
    h5::Handle set(
        H5Dcreate2(file, name, type, space.get(), H5P_DEFAULT, create.get(), H5P_DEFAULT),
        H5Dclose);
    return;
  }
  // Written with the fuzzer's values when small enough.
  hsize_t count = 1;
  for (int d = 0; d < rank; ++d) count *= dims[d];
  if (count > 4096) return;
  std::vector<double> values(count);
  for (auto& v : values) v = type == H5T_NATIVE_FLOAT ? anyFloat(in) : double(anyInteger(in));
  h5::Handle set(H5Dcreate2(file, name, type, space.get(), H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT),
                 H5Dclose);
  if (set.get() >= 0 && count > 0)
    H5Dwrite(set.get(), H5T_NATIVE_DOUBLE, H5S_ALL, H5S_ALL, H5P_DEFAULT, values.data());
}

template <size_t A, size_t B, size_t C>
void edit(const std::string& path, FuzzedDataProvider& in, const char* const (&ints)[A],
          const char* const (&strings)[B], const char* const (&sets)[C]) {
  h5::Handle file(H5Fopen(path.c_str(), H5F_ACC_RDWR, H5P_DEFAULT), H5Fclose);
  if (file.get() < 0) return;
  const int edits = in.ConsumeIntegralInRange(0, 4);
  for (int e = 0; e < edits && in.remaining_bytes() > 0; ++e) {
    const hid_t f = file.get();
    switch (in.ConsumeIntegralInRange(0, 2)) {
      case 0: {
        const char* name = ints[in.ConsumeIntegralInRange<size_t>(0, A - 1)];
        if (H5Aexists(f, name) > 0) H5Adelete(f, name);
        if (in.ConsumeBool()) h5::writeAttribute(f, name, anyInteger(in), path);
        break;
      }
      case 1: {
        const char* name = strings[in.ConsumeIntegralInRange<size_t>(0, B - 1)];
        if (H5Aexists(f, name) > 0) H5Adelete(f, name);
        h5::writeAttribute(f, name, in.ConsumeRandomLengthString(40), path);
        break;
      }
      default:
        replaceDataset(f, sets[in.ConsumeIntegralInRange<size_t>(0, C - 1)], in);
    }
  }
}

/// A small valid transport: rows of the fuzzer's values on a 6x1x1 or 6x2x2 lattice.
void writeTransport(const std::string& path, FuzzedDataProvider& in) {
  TransportHeader h;
  h.camera.size = {in.ConsumeIntegralInRange(1, 4), in.ConsumeIntegralInRange(1, 4)};
  h.cubemapResolution = in.ConsumeIntegralInRange(1, 2);
  h.precision = in.ConsumeBool() ? Precision::F16 : Precision::F32;
  if (in.ConsumeBool()) {  // R, G and B rows of bounced light
    h.channels = 3;
    h.bounces = 1;
    h.indirectSamples = 8;
  }
  h.scene = "fuzz";
  for (int p = 0; p < h.camera.size.pixels(); ++p)
    if (in.ConsumeBool()) {
      h.pixels.push_back(p);
      h.albedo.insert(h.albedo.end(), {0.5f, 0.5f, 0.5f});
      h.coverage.push_back(1.0f);
      h.normals.insert(h.normals.end(), {0.0f, 0.0f, 1.0f});
    }
  std::vector<float> rows(h.rows() * h.rowLength());
  for (auto& v : rows) v = in.ConsumeFloatingPointInRange(0.0f, 1.0f);
  TransportWriter writer(path, h);
  writer.writeRows(0, h.rows(), rows.data());
  writer.finish();
}

/// A small valid model: one cluster holding every row, rank 0..N.
void writeSmallModel(const std::string& path, FuzzedDataProvider& in) {
  Model m;
  m.geometry.camera.size = {in.ConsumeIntegralInRange(1, 3), in.ConsumeIntegralInRange(1, 3)};
  m.geometry.cubemapResolution = 1;
  const int rows = m.geometry.camera.size.pixels();
  for (int p = 0; p < rows; ++p) {
    m.geometry.pixels.push_back(p);
    m.geometry.albedo.insert(m.geometry.albedo.end(), {0.5f, 0.5f, 0.5f});
    m.geometry.coverage.push_back(1.0f);
    m.geometry.normals.insert(m.geometry.normals.end(), {0.0f, 0.0f, 1.0f});
  }
  m.method = "global";
  m.settings = "{}";
  const int n = in.ConsumeIntegralInRange(1, 6), rank = in.ConsumeIntegralInRange(0, n);
  m.globalBasis = Eigen::MatrixXf::Identity(6, n);
  m.precision = in.PickValueInArray({CoeffPrecision::F32, CoeffPrecision::F16, CoeffPrecision::I8});
  m.clusterRows.resize(rows);
  for (int p = 0; p < rows; ++p) m.clusterRows[p] = p;
  m.rowOffsets = {0, rows};
  m.ranks = {rank};
  m.basisOffsets = {0, n * rank};
  m.bases.assign(n * rank, 0.5f);
  m.means.assign(n, 0.0f);
  m.coefficientOffsets = {0, static_cast<long long>(rows) * rank};
  m.coeffF32.resize(rows * rank);
  for (auto& v : m.coeffF32) v = in.ConsumeFloatingPointInRange(-1.0f, 1.0f);
  const CoeffPrecision wanted = m.precision;
  m.precision = CoeffPrecision::F32;
  storeCoefficients(m, wanted);
  writeModel(m, path);
}

}  // namespace
}  // namespace acpca

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, size_t size) {
  using namespace acpca;
  FuzzedDataProvider in(data, size);
  const std::string path = fuzz::inputPath("-headers.h5");
  std::remove(path.c_str());
  const bool model = in.ConsumeBool();
  if (model) {
    writeSmallModel(path, in);
    edit(path, in, kModelInts, kModelStrings, kModelSets);
    return fuzz::runReader([&] {
      const Model m = readModel(path);
      ModelRelighter relighter(m);
      const LatticeLighting light = computeLighting(*loadEnvironment("constant:1"),
                                                    CubeLattice(m.geometry.cubemapResolution), {});
      fuzz::requireFinite(relighter.relight(light), "relit value");
    });
  }
  writeTransport(path, in);
  edit(path, in, kTransportInts, kTransportStrings, kTransportSets);
  return fuzz::runReader([&] {
    const TransportReader reader(path);
    const LatticeLighting light = computeLighting(
        *loadEnvironment("constant:1"), CubeLattice(reader.header().cubemapResolution), {});
    fuzz::requireFinite(denseRelight(reader, {light})[0], "relit value");
  });
}
