#pragma once
// The run-time hot path (docs/design.md section 6, [Mahajan07] eq. 17): per frame,
//   L_g = V_g^T L            (N x 3, over the directions some pixel sees)
//   L_i = W_i^T L_g          (n_i x 3 per cluster, plus mu_i . L_g with a mean)
//   b_p = albedo_p (u_p . L_i)
// Three TBB phases: L_g, every cluster's L_i, then the pixels band by band.
// A cluster's rows lie all over the image, so shading cluster by cluster wrote
// pixels all over it, each write fetching its cache line from memory (a quarter
// of a frame at 1024x1024). Chunks of 16 rows are instead stored and shaded in
// bands of the image (by their first row), so a thread's writes stay in a few
// hundred KB and its reads are one sequential stream. Each value is computed by
// one task in a fixed order, so the image is the same for any thread count.
// All memory is allocated when the relighter is built; a frame allocates
// nothing.
#include <array>
#include <cstdint>
#include <vector>

#include "cluster/model.h"
#include "core/huge_pages.h"
#include "relight/environment.h"

namespace acpca {

class ModelRelighter {
 public:
  /// Repacks the model's coefficients for the SIMD loop (k-major chunks of 16
  /// rows per cluster); the model may be released afterwards.
  explicit ModelRelighter(const Model& model);

  /// Uses only each cluster's first min(n_i, k) bases ([Lehtinen03]'s quality/speed
  /// trade: PCA bases come in order of importance). k < 0: all of them.
  void setMaxRank(int k);
  /// Uses the first ceil(fraction * n_i) bases of each cluster, fraction in [0, 1].
  void setRankFraction(double fraction);

  /// Relights one lighting (3 l values, RGB per texel) into rgb: 3 floats per
  /// occupied row, albedo applied, in the model's row order.
  void relight(const LatticeLighting& lighting, float* rgb);
  std::vector<float> relight(const LatticeLighting& lighting);
  /// Relights straight into an image (width x height pixels of `channels`
  /// floats, row-major): each occupied pixel gets coverage x its relit value
  /// added to its first three channels, the caller having put the background,
  /// weighted by 1 - coverage, there first (ImageComposer::background).
  void relightInto(const LatticeLighting& lighting, float* pixels, int channels);

  /// Bases each cluster uses at the current rank limit.
  const std::vector<int>& activeRanks() const { return activeRanks_; }
  const TransportHeader& geometry() const { return geometry_; }
  long long rows() const { return geometry_.rows(); }
  /// Bytes of model data one frame reads at the current rank limit: bases,
  /// coefficients (with chunk padding), row indices and albedo.
  long long bytesPerFrame() const;
  /// Multiply-adds per pixel at the current rank limit (eq. 18, per channel).
  double costPerPixel() const;

 private:
  struct Chunk {
    int cluster;
    long long coefficientOffset;  ///< element index of the chunk's k-major block
  };
  /// Where a frame's values go: rgb[stride * target[lane] + c] (= or += weight).
  struct Output {
    float* values;
    int stride;
    bool image;  ///< add coverage-weighted values at pixel indices, else set rows
  };
  void lightGlobal(const LatticeLighting& lighting);
  template <typename B>
  void lightCluster(int c, const HugePageVector<B>& bases);
  template <typename T>
  void shadeBand(int band, const HugePageVector<T>& coefficients, const Output& out) const;
  template <typename B, typename T>
  void shadeAll(const HugePageVector<B>& bases, const HugePageVector<T>& coefficients,
                const Output& out);
  void shadeAll(const Output& out);

  TransportHeader geometry_;
  CoeffPrecision precision_;
  int globalBases_ = 0;
  bool hasMean_ = false;

  std::vector<int> seenTexels_;  ///< row elements (texel, or channel x texel) V_g sees
  /// With R, G and B rows: where each channel's elements start in seenTexels_.
  std::array<int, 4> partStart_{};
  HugePageVector<float> globalBasis_;  ///< N columns of |seen| values (V_g^T, row by row)
  CoeffPrecision basisPrecision_;
  /// W_i^T in tiles of 16 bases: per tile N x 16 values, global index major.
  HugePageVector<float> bases_;
  HugePageVector<std::uint16_t> basesF16_;  ///< the same in half, for f16-basis models
  std::vector<long long> basisOffset_;      ///< per cluster
  std::vector<float> means_;                ///< C x N when the model has means
  std::vector<int> ranks_, activeRanks_;
  std::vector<long long> lightingOffset_;  ///< per cluster, into clusterLighting_ (x3)
  std::vector<float> scale_;               ///< per cluster basis: i8 step, else 1

  /// Chunks in the order a frame shades them (and their coefficients are
  /// stored): by image band of their first row, then cluster.
  std::vector<Chunk> chunks_;
  std::vector<long long> bandChunks_;         ///< per band, its first chunk (+ end)
  HugePageVector<std::int32_t> chunkRows_;    ///< 16 per chunk, -1 for padding
  HugePageVector<std::int32_t> chunkPixels_;  ///< the same rows' pixel indices
  HugePageVector<float> chunkCoverage_;       ///< 16 per chunk: the rows' coverage
  std::vector<std::uint8_t>
      chunkConsecutive_;               ///< per chunk: kRowsConsecutive | kPixelsConsecutive
  HugePageVector<float> chunkAlbedo_;  ///< 48 per chunk: R x16, G x16, B x16
  HugePageVector<float> coeffF32_;
  HugePageVector<std::uint16_t> coeffF16_;
  HugePageVector<std::int8_t> coeffI8_;

  // Per-frame scratch, sized once.
  std::vector<float> light_;              ///< 3 x |seen|, channel-major
  std::vector<float> globalLighting_;     ///< 3 x N, channel-major
  std::vector<float> globalLightingRgb_;  ///< N x 3, interleaved
  std::vector<float> clusterLighting_;    ///< per cluster n_i x 3, interleaved
  std::vector<float> meanTerm_;           ///< 3 per cluster
};

}  // namespace acpca
