// The in-memory dense relight (the yardstick of speed-ups) against the file.
#include "eval/sparse_transport.h"

#include <gtest/gtest.h>

#include <cmath>

#include <tbb/global_control.h>

#include "core/statistics.h"
#include "lighting/environment.h"
#include "lighting/lighting.h"
#include "relight/dense_relight.h"
#include "tests/lighting_support.h"
#include "tests/test_support.h"

namespace acpca {
namespace {

class SparsePlant : public test::SmallPlantSuite {
 protected:
  static std::vector<LatticeLighting> lightings() { return test::plantLightings(); }
};

TEST_F(SparsePlant, SparseDenseRelightSkipsZerosAndMatchesTheFile) {
  const TransportReader t(path());
  const auto all = lightings();
  const auto dense = denseRelight(t, all);
  SparseTransport sparse(t);
  // Every row is zero below its horizon, so at most about half plus the
  // segments that straddle it are kept.
  EXPECT_GT(sparse.keptFraction(), 0.05);
  EXPECT_LT(sparse.keptFraction(), 0.75);
  for (size_t k = 0; k < all.size(); ++k) {
    std::vector<float> one, two = sparse.relight(all[k]);
    {
      tbb::global_control limit(tbb::global_control::max_allowed_parallelism, 1);
      one = sparse.relight(all[k]);
    }
    EXPECT_EQ(one, two);
    // The file is f32; the sparse copy rounds T to half: 2^-11 relative per entry.
    EXPECT_LT(relativeL2(two, dense[k]), std::ldexp(1.0, -11));
  }
}

TEST(SparseTransport, RgbRowsRelightAsTheFile) {
  const TransportReader t(test::fixture("bounced-plant"));
  ASSERT_EQ(t.header().channels, 3);
  const auto all = test::plantLightings();
  const auto dense = denseRelight(t, all);
  SparseTransport sparse(t);
  for (size_t k = 0; k < all.size(); ++k)
    EXPECT_LT(relativeL2(sparse.relight(all[k]), dense[k]), std::ldexp(1.0, -11));
}

}  // namespace
}  // namespace acpca
