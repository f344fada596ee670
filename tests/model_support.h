#pragma once
// The model suites' shared check: two models hold the same clusters and
// values, array by array (a round trip, a model written in pieces, a
// resumed build).
#include <gtest/gtest.h>

#include "model/model.h"

namespace acpca::test {

inline void expectSameModelArrays(const Model& back, const Model& expected) {
  EXPECT_EQ(back.method, expected.method);
  EXPECT_EQ(back.precision, expected.precision);
  EXPECT_TRUE(back.globalBasis == expected.globalBasis);
  EXPECT_EQ(back.ranks, expected.ranks);
  EXPECT_EQ(back.clusterRows, expected.clusterRows);
  EXPECT_EQ(back.rowOffsets, expected.rowOffsets);
  EXPECT_EQ(back.basisOffsets, expected.basisOffsets);
  EXPECT_EQ(back.coefficientOffsets, expected.coefficientOffsets);
  EXPECT_EQ(back.bases, expected.bases);
  EXPECT_EQ(back.means, expected.means);
  EXPECT_EQ(back.coeffF32, expected.coeffF32);
  EXPECT_EQ(back.coeffF16, expected.coeffF16);
  EXPECT_EQ(back.coeffI8, expected.coeffI8);
  EXPECT_EQ(back.coeffScale, expected.coeffScale);
  EXPECT_DOUBLE_EQ(back.transportError, expected.transportError);
  EXPECT_EQ(back.geometry.pixels, expected.geometry.pixels);
  EXPECT_EQ(back.geometry.albedo, expected.geometry.albedo);
}

}  // namespace acpca::test
