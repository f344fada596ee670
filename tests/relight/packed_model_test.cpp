// A model file read cluster by cluster into the relighter's layout
// (readPackedModel) against the model read whole and packed: the same arrays
// at every precision, through HDF5 where the file's layout asks for it, and
// the same refusals of values no relight may use.
#include "relight/packed_model.h"

#include <gtest/gtest.h>

#include "core/error.h"
#include "core/half.h"
#include "model/model_file.h"
#include "tests/model_support.h"
#include "tests/temp_dir.h"
#include "transport/dataset_slices.h"
#include "transport/hdf5_handles.h"

namespace acpca {
namespace {

void expectSamePacking(const PackedModel& a, const PackedModel& b) {
  EXPECT_EQ(a.method, b.method);
  EXPECT_EQ(a.globalBases, b.globalBases);
  EXPECT_EQ(a.ranks, b.ranks);
  EXPECT_EQ(a.scale, b.scale);
  EXPECT_EQ(a.means, b.means);
  EXPECT_EQ(a.seenTexels, b.seenTexels);
  EXPECT_EQ(a.partStart, b.partStart);
  EXPECT_TRUE(a.globalBasis == b.globalBasis);
  EXPECT_TRUE(a.bases == b.bases);
  EXPECT_TRUE(a.basesF16 == b.basesF16);
  EXPECT_EQ(a.basisOffset, b.basisOffset);
  ASSERT_EQ(a.chunks.size(), b.chunks.size());
  for (size_t i = 0; i < a.chunks.size(); ++i) {
    EXPECT_EQ(a.chunks[i].cluster, b.chunks[i].cluster) << i;
    EXPECT_EQ(a.chunks[i].coefficientOffset, b.chunks[i].coefficientOffset) << i;
  }
  EXPECT_EQ(a.spanChunks, b.spanChunks);
  EXPECT_TRUE(a.chunkRows == b.chunkRows);
  EXPECT_TRUE(a.chunkPixels == b.chunkPixels);
  EXPECT_TRUE(a.chunkAlbedo == b.chunkAlbedo);
  EXPECT_TRUE(a.coeffF32 == b.coeffF32);
  EXPECT_TRUE(a.coeffF16 == b.coeffF16);
  EXPECT_TRUE(a.coeffI8 == b.coeffI8);
}

/// bandedModel with half bases and means where asked (values rounded to half).
Model shapedModel(CoeffPrecision precision, CoeffPrecision basisPrecision) {
  Model m = test::bandedModel(precision, 7);
  m.method = "adaptive-binary";
  m.basisPrecision = basisPrecision;
  if (basisPrecision == CoeffPrecision::F16)
    for (auto* values : {&m.bases, &m.means}) {
      std::vector<std::uint16_t> h(values->size());
      floatToHalf(values->data(), h.data(), h.size());
      halfToFloat(h.data(), values->data(), h.size());
    }
  return m;
}

/// Overwrites one value of a float dataset in place.
void patchValue(const std::string& path, const std::string& name, hsize_t at, float value) {
  const h5::Handle file(H5Fopen(path.c_str(), H5F_ACC_RDWR, H5P_DEFAULT), H5Fclose);
  const h5::Handle set(H5Dopen2(file.get(), name.c_str(), H5P_DEFAULT), H5Dclose);
  const h5::Handle space(H5Dget_space(set.get()), H5Sclose);
  const int rank = H5Sget_simple_extent_ndims(space.get());
  std::vector<hsize_t> start(rank, 0), count(rank, 1), dims(rank);
  H5Sget_simple_extent_dims(space.get(), dims.data(), nullptr);
  for (int d = rank - 1; d >= 0; --d) start[d] = at % dims[d], at /= dims[d];
  ASSERT_GE(H5Sselect_hyperslab(space.get(), H5S_SELECT_SET, start.data(), nullptr, count.data(),
                                nullptr),
            0);
  const h5::Handle one(H5Screate_simple(1, count.data(), nullptr), H5Sclose);
  ASSERT_GE(H5Dwrite(set.get(), H5T_NATIVE_FLOAT, one.get(), space.get(), H5P_DEFAULT, &value), 0);
}

/// Writes dataset `name` again, chunked by 100 entries of its first index,
/// and so out of reach of direct reads.
void rewriteChunked(const std::string& path, const std::string& name) {
  const h5::Handle file(H5Fopen(path.c_str(), H5F_ACC_RDWR, H5P_DEFAULT), H5Fclose);
  const h5::Handle set(H5Dopen2(file.get(), name.c_str(), H5P_DEFAULT), H5Dclose);
  const h5::Handle type(H5Dget_type(set.get()), H5Tclose);
  const h5::Handle space(H5Dget_space(set.get()), H5Sclose);
  const hsize_t size = H5Sget_simple_extent_npoints(space.get());
  const int rank = H5Sget_simple_extent_ndims(space.get());
  std::vector<hsize_t> chunk(rank);
  H5Sget_simple_extent_dims(space.get(), chunk.data(), nullptr);
  chunk[0] = std::min<hsize_t>(chunk[0], 100);  // several chunks, the last one partly filled
  std::vector<char> bytes(size * H5Tget_size(type.get()));
  ASSERT_GE(H5Dread(set.get(), type.get(), H5S_ALL, H5S_ALL, H5P_DEFAULT, bytes.data()), 0);
  ASSERT_GE(H5Ldelete(file.get(), name.c_str(), H5P_DEFAULT), 0);
  const h5::Handle creation(H5Pcreate(H5P_DATASET_CREATE), H5Pclose);
  ASSERT_GE(H5Pset_chunk(creation.get(), rank, chunk.data()), 0);
  const h5::Handle chunked(H5Dcreate2(file.get(), name.c_str(), type.get(), space.get(),
                                      H5P_DEFAULT, creation.get(), H5P_DEFAULT),
                           H5Dclose);
  ASSERT_GE(H5Dwrite(chunked.get(), type.get(), H5S_ALL, H5S_ALL, H5P_DEFAULT, bytes.data()), 0);
}

bool readsDirectly(const std::string& path, const std::string& name, hid_t type, hsize_t size) {
  const h5::Handle file = h5::openFileReadOnly(path);
  return DatasetSlices(file.get(), path, name, type, {size}, path).direct();
}

TEST(PackedModel, AFileReadClusterByClusterPacksAsTheWholeModel) {
  // Clusters of 9001 and 7000 rows are read in several runs, one of 0 rank.
  for (CoeffPrecision precision : {CoeffPrecision::F32, CoeffPrecision::F16, CoeffPrecision::I8})
    for (CoeffPrecision basis : {CoeffPrecision::F32, CoeffPrecision::F16}) {
      SCOPED_TRACE(std::string(coeffPrecisionName(precision)) + " coefficients, " +
                   coeffPrecisionName(basis) + " bases");
      const Model m = shapedModel(precision, basis);
      test::TempDir dir;
      const std::string path = dir.file("m.h5");
      writeModel(m, path);
      EXPECT_TRUE(readsDirectly(path, "coefficients",
                                precision == CoeffPrecision::F32  ? H5T_NATIVE_FLOAT
                                : precision == CoeffPrecision::I8 ? H5T_NATIVE_INT8
                                                                  : h5::halfType().get(),
                                m.coefficientOffsets.back()));
      const std::shared_ptr<const PackedModel> read = readPackedModel(path);
      expectSamePacking(*read, PackedModel(m));
      expectSamePacking(*read, PackedModel(readModel(path)));
      EXPECT_EQ(read->clusterOfRow(), m.clusterOfRow());
    }
}

TEST(PackedModel, AModelWithoutGlobalBasesPacksToo) {
  // N = 0: no bases, means or coefficients; every relit value is 0.
  Model m = shapedModel(CoeffPrecision::F32, CoeffPrecision::F32);
  m.globalBasis = Eigen::MatrixXf(m.globalBasis.rows(), 0);
  std::fill(m.ranks.begin(), m.ranks.end(), 0);
  std::fill(m.basisOffsets.begin(), m.basisOffsets.end(), 0);
  std::fill(m.coefficientOffsets.begin(), m.coefficientOffsets.end(), 0);
  m.bases.clear();
  m.means.clear();
  m.coeffF32.clear();
  m.coeffScale.clear();
  test::TempDir dir;
  const std::string path = dir.file("m.h5");
  writeModel(m, path);
  expectSamePacking(*readPackedModel(path), PackedModel(m));
}

TEST(PackedModel, ChunkedDatasetsAreReadThroughHdf5ToTheSameArrays) {
  const Model m = shapedModel(CoeffPrecision::F32, CoeffPrecision::F32);
  test::TempDir dir;
  const std::string path = dir.file("m.h5");
  writeModel(m, path);
  for (const char* name : {"bases", "coefficients", "global_basis"}) rewriteChunked(path, name);
  EXPECT_FALSE(readsDirectly(path, "coefficients", H5T_NATIVE_FLOAT, m.coefficientOffsets.back()));
  EXPECT_FALSE(readsDirectly(path, "bases", H5T_NATIVE_FLOAT, m.basisOffsets.back()));
  expectSamePacking(*readPackedModel(path), PackedModel(m));
}

TEST(PackedModel, ValuesNoRelightMayUseAreRefusedAsReadModelRefusesThem) {
  const Model m = shapedModel(CoeffPrecision::F32, CoeffPrecision::F32);
  const float nan = std::numeric_limits<float>::quiet_NaN();
  const float inf = std::numeric_limits<float>::infinity();
  struct Case {
    const char* dataset;
    hsize_t at;
    float value;
    const char* message;
  };
  const long long lastCoefficient = m.coefficientOffsets.back() - 1;
  for (const Case& c :
       {Case{"bases", 40, nan, "non-finite basis value"},
        Case{"means", 3, inf, "non-finite cluster mean"},
        Case{"coefficients", 12345, -inf, "non-finite coefficient"},
        Case{"coefficients", hsize_t(lastCoefficient), nan, "non-finite coefficient"},
        Case{"global_basis", 30, nan, "non-finite global basis value"},
        Case{"coefficients", 77, 1e37f, "values out of range"}}) {
    SCOPED_TRACE(std::string(c.dataset) + " " + c.message);
    test::TempDir dir;
    const std::string path = dir.file("m.h5");
    writeModel(m, path);
    patchValue(path, c.dataset, c.at, c.value);
    for (bool packed : {true, false}) {
      try {
        if (packed)
          readPackedModel(path);
        else
          readModel(path);
        ADD_FAILURE() << "accepted";
      } catch (const UserError& e) {
        EXPECT_NE(std::string(e.what()).find(path + ": " + c.message), std::string::npos)
            << e.what();
      }
    }
  }
}

}  // namespace
}  // namespace acpca
