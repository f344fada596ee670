#include "cluster/partition.h"

#include <tbb/parallel_for.h>

#include <algorithm>
#include <functional>
#include <limits>
#include <numeric>
#include <random>

#include "cluster/partition_support.h"
#include "cluster/pca.h"
#include "cluster/symmetric_eigen.h"
#include "model/cost_model.h"

#include <Eigen/QR>
#include "core/error.h"

namespace acpca {

namespace {

/// Row index of every pixel, -1 for background.
std::vector<int> rowImage(const ClusterInput& in) {
  std::vector<int> image(static_cast<size_t>(in.size.pixels()), -1);
  for (size_t r = 0; r < in.pixels->size(); ++r) image[(*in.pixels)[r]] = static_cast<int>(r);
  return image;
}

struct Block {
  int x0, y0, side;
};

std::vector<int> rowsInBlock(const ClusterInput& in, const std::vector<int>& image,
                             const Block& b) {
  std::vector<int> rows;
  for (int y = b.y0; y < std::min(b.y0 + b.side, in.size.height); ++y)
    for (int x = b.x0; x < std::min(b.x0 + b.side, in.size.width); ++x)
      if (const int r = image[static_cast<size_t>(y) * in.size.width + x]; r >= 0)
        rows.push_back(r);
  std::sort(rows.begin(), rows.end());
  return rows;
}

std::vector<Block> rootBlocks(const ClusterInput& in, int side) {
  std::vector<Block> roots;
  for (int y = 0; y < in.size.height; y += side)
    for (int x = 0; x < in.size.width; x += side) roots.push_back({x, y, side});
  return roots;
}

}  // namespace

int rankOf(const ClusterInput& in, const std::vector<int>& rows) {
  if (rows.empty()) return 0;
  return rankToTolerance(gatherRows(in, rows, in.globalBases()), in.tolerance, in.mean);
}

double costOf(const ClusterInput& in, const std::vector<int>& rows, int rank) {
  return clusterCost(rank + (in.mean ? 1 : 0), static_cast<long long>(rows.size()),
                     in.globalBases());
}

Partition singleCluster(const ClusterInput& in) {
  std::vector<int> all(in.rows());
  std::iota(all.begin(), all.end(), 0);
  return all.empty() ? Partition{} : Partition{all};
}

Partition fixedBlocks(const ClusterInput& in, int block) {
  if (block < 1) throw ParameterError("block side", block, "must be >= 1");
  const std::vector<int> image = rowImage(in);
  Partition p;
  for (const Block& b : rootBlocks(in, block))
    if (auto rows = rowsInBlock(in, image, b); !rows.empty()) p.push_back(std::move(rows));
  return p;
}

Partition adaptiveQuadTree(const ClusterInput& in, const QuadTreeOptions& options) {
  if (options.rootBlock < 1 || options.minBlock < 1)
    throw UserError("adaptive-quad: block sizes must be >= 1");
  const std::vector<int> image = rowImage(in);
  struct Node {
    Block block;
    std::vector<int> rows;
    double cost = 0;
  };
  const auto makeNode = [&](const Block& b) {
    Node n{b, rowsInBlock(in, image, b), 0};
    n.cost = costOf(in, n.rows, rankOf(in, n.rows));
    return n;
  };
  const auto children = [&](const Node& n) {
    std::vector<Block> blocks;
    const int half = (n.block.side + 1) / 2;
    for (int dy = 0; dy < 2; ++dy)
      for (int dx = 0; dx < 2; ++dx) {
        const Block c{n.block.x0 + dx * half, n.block.y0 + dy * half, half};
        if (c.x0 < in.size.width && c.y0 < in.size.height) blocks.push_back(c);
      }
    std::vector<Node> nodes(blocks.size());
    tbb::parallel_for(size_t(0), blocks.size(), [&](size_t i) { nodes[i] = makeNode(blocks[i]); });
    std::erase_if(nodes, [](const Node& c) { return c.rows.empty(); });
    return nodes;
  };
  // Greedy (paper): split while the children are cheaper, recurse into them.
  std::function<void(Node&, Partition&)> greedy = [&](Node& n, Partition& out) {
    if (n.block.side > options.minBlock && n.rows.size() > 1) {
      std::vector<Node> kids = children(n);
      double sum = 0;
      for (const auto& k : kids) sum += k.cost;
      if (sum < n.cost || kids.size() == 1) {  // one child holds the same rows: look deeper
        for (auto& k : kids) greedy(k, out);
        return;
      }
    }
    out.push_back(std::move(n.rows));
  };
  // Exact: best(node) = min(c(node), sum of best(children)), over the whole tree.
  std::function<double(Node&, Partition&)> exact = [&](Node& n, Partition& out) {
    if (n.block.side > options.minBlock && n.rows.size() > 1) {
      std::vector<Node> kids = children(n);
      Partition below;
      double sum = 0;
      for (auto& k : kids) sum += exact(k, below);
      if (sum < n.cost) {
        for (auto& c : below) out.push_back(std::move(c));
        return sum;
      }
    }
    out.push_back(std::move(n.rows));
    return n.cost;
  };
  return concatInOrder(rootBlocks(in, options.rootBlock), [&](const Block& b) {
    Partition out;
    Node root = makeNode(b);
    if (root.rows.empty()) return out;
    if (options.exact)
      exact(root, out);
    else
      greedy(root, out);
    return out;
  });
}

namespace {

/// Mean and leading principal directions of one cluster during CPCA, in float:
/// assignment compares reconstruction errors, which float holds to far better
/// than the differences that decide it.
struct ClusterFit {
  Eigen::RowVectorXf mean;
  Eigen::MatrixXf basis;  // N x r
};

ClusterFit fitCluster(const Eigen::MatrixXf& rows, int rank) {
  ClusterFit f;
  f.mean = (rows.cast<double>().colwise().sum() / double(rows.rows())).cast<float>();
  const Eigen::MatrixXf centred = rows.rowwise() - f.mean;
  const int r = std::min<int>(rank, std::max<Eigen::Index>(0, rows.rows() - 1));
  if (r == 0 || centred.squaredNorm() == 0) {
    f.basis.resize(rows.cols(), 0);
    return f;
  }
  // The leading r directions by randomized subspace iteration (Halko et al.
  // 2011): a few passes over the rows instead of a full N x N eigensolve, and
  // assignment needs no more precision. Fixed seed: deterministic.
  const Eigen::Index n = rows.cols(), q = std::min<Eigen::Index>(n, r + 8);
  std::mt19937_64 rng(12345);
  std::normal_distribution<float> normal;
  Eigen::MatrixXf y(n, q);
  for (Eigen::Index i = 0; i < y.size(); ++i) y.data()[i] = normal(rng);
  for (int pass = 0; pass < 3; ++pass) {
    const Eigen::MatrixXf z = centred.transpose() * (centred * y);
    y = Eigen::HouseholderQR<Eigen::MatrixXf>(z).householderQ() * Eigen::MatrixXf::Identity(n, q);
  }
  const Eigen::MatrixXf b = centred * y;  // p x q
  const SymmetricEigen small = symmetricEigen((b.transpose() * b).cast<double>(), true);
  const int kept = std::min<int>(r, rankForEnergy(small.values, small.values.sum(), 1.0));
  f.basis = y * small.vectors.leftCols(kept).cast<float>();
  return f;
}

/// k-means++ seeding (Arthur and Vassilvitskii 2007) on the rows: k seeds,
/// each row labelled with its nearest.
std::vector<int> kMeansPlusPlusLabels(const RowMatrixF& xr, int k, std::uint64_t seed) {
  const int n = static_cast<int>(xr.rows());
  std::mt19937_64 rng(seed);
  std::vector<int> seeds{static_cast<int>(rng() % n)};
  Eigen::VectorXd d2 = (xr.rowwise() - xr.row(seeds[0])).rowwise().squaredNorm().cast<double>();
  while (static_cast<int>(seeds.size()) < k) {
    const double total = d2.sum();
    int pick = 0;
    if (total > 0) {
      double u = (rng() >> 11) * 0x1.0p-53 * total;
      while (pick < n - 1 && (u -= d2[pick]) > 0) ++pick;
    } else {
      pick = static_cast<int>(rng() % n);
    }
    seeds.push_back(pick);
    d2 = d2.cwiseMin((xr.rowwise() - xr.row(pick)).rowwise().squaredNorm().cast<double>());
  }
  std::vector<int> label(n);
  Eigen::MatrixXf centres(k, xr.cols());
  for (int c = 0; c < k; ++c) centres.row(c) = xr.row(seeds[c]);
  const Eigen::MatrixXf dots = xr * centres.transpose();
  const Eigen::VectorXf cn = centres.rowwise().squaredNorm();
  for (int i = 0; i < n; ++i) (cn - 2 * dots.row(i).transpose()).minCoeff(&label[i]);
  return label;
}

/// Two halves by the sign of each row's first principal coefficient (the
/// split Sloan's CPCA and principal-direction bisection start from).
std::vector<int> principalSignLabels(const RowMatrixF& x) {
  const ClusterFit all = fitCluster(x, 1);
  std::vector<int> label(x.rows(), 0);
  if (all.basis.cols() == 0) return label;  // every row the same: one side
  const Eigen::VectorXf side = (x.rowwise() - all.mean) * all.basis.col(0);
  for (Eigen::Index i = 0; i < x.rows(); ++i) label[i] = side[i] > 0 ? 1 : 0;
  return label;
}

}  // namespace

Partition cpca(const ClusterInput& in, const std::vector<int>& rowsIn, const CpcaOptions& o) {
  if (o.clusters < 1) throw ParameterError("clusters", o.clusters, "must be >= 1");
  const int n = static_cast<int>(rowsIn.size());
  const int k = std::min(o.clusters, n);
  if (k <= 1) return n ? Partition{rowsIn} : Partition{};
  // Row-major: assignment reads whole rows.
  const RowMatrixF x = gatherRows(in, rowsIn, in.clusteringWidth());
  const Eigen::VectorXf norms = x.rowwise().squaredNorm();
  // A few leading global coefficients carry most of the energy: good enough to
  // seed and to shortlist candidate clusters.
  const int reduced = std::min<int>(64, static_cast<int>(x.cols()));
  const RowMatrixF xr = x.leftCols(reduced);

  std::vector<int> label =
      k == 2 && o.splitBySign ? principalSignLabels(x) : kMeansPlusPlusLabels(xr, k, o.seed);

  const int candidates = std::min(o.candidates, k);
  for (int iteration = 0; iteration < o.iterations; ++iteration) {
    std::vector<std::vector<int>> members(k);
    for (int i = 0; i < n; ++i) members[label[i]].push_back(i);
    std::vector<ClusterFit> fits(k);
    tbb::parallel_for(0, k, [&](int c) {
      if (members[c].empty()) return;
      Eigen::MatrixXf rows(members[c].size(), x.cols());
      for (size_t i = 0; i < members[c].size(); ++i) rows.row(i) = x.row(members[c][i]);
      fits[c] = fitCluster(rows, o.iterationRank);
    });
    // Shortlist by distance to the means on the reduced rows, then the exact
    // reconstruction error e = |x - mu|^2 - |P^T (x - mu)|^2 on the full rows.
    RowMatrixF meansReduced = RowMatrixF::Zero(k, reduced);
    for (int c = 0; c < k; ++c)
      if (!members[c].empty()) meansReduced.row(c) = fits[c].mean.head(reduced);
    std::vector<int> next(n);
    std::vector<double> error(n);
    tbb::parallel_for(
        tbb::blocked_range<int>(0, n, 256), [&](const tbb::blocked_range<int>& range) {
          std::vector<std::pair<double, int>> order(k);
          for (int i = range.begin(); i < range.end(); ++i) {
            for (int c = 0; c < k; ++c)
              order[c] = {members[c].empty() ? std::numeric_limits<double>::infinity()
                                             : (xr.row(i) - meansReduced.row(c)).squaredNorm(),
                          c};
            std::partial_sort(order.begin(), order.begin() + candidates, order.end());
            double best = std::numeric_limits<double>::infinity();
            int bestCluster = label[i];
            for (int q = 0; q < candidates; ++q) {
              const int c = order[q].second;
              if (members[c].empty()) continue;
              const Eigen::RowVectorXf centred = x.row(i) - fits[c].mean;
              const double e =
                  double(centred.squaredNorm()) - double((centred * fits[c].basis).squaredNorm());
              if (e < best - 1e-12 * norms[i]) best = e, bestCluster = c;
            }
            next[i] = bestCluster;
            error[i] = best;
          }
        });
    // Re-seed emptied clusters with the worst-reconstructed rows.
    std::vector<int> count(k, 0);
    for (int c : next) ++count[c];
    std::vector<int> worst(n);
    std::iota(worst.begin(), worst.end(), 0);
    std::stable_sort(worst.begin(), worst.end(), [&](int a, int b) { return error[a] > error[b]; });
    int w = 0;
    for (int c = 0; c < k; ++c)
      if (count[c] == 0 && w < n) {
        while (w < n && count[next[worst[w]]] <= 1) ++w;
        if (w < n) --count[next[worst[w]]], next[worst[w]] = c, ++count[c], ++w;
      }
    const bool moved = next != label;
    label = next;
    if (!moved) break;
  }
  Partition p(k);
  for (int i = 0; i < n; ++i) p[label[i]].push_back(rowsIn[i]);
  std::erase_if(p, [](const std::vector<int>& c) { return c.empty(); });
  for (auto& c : p) std::sort(c.begin(), c.end());
  return p;
}

}  // namespace acpca
