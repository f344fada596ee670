#pragma once
// The model file (HDF5, docs/formats.md): the image header shared with
// transport files, then the global basis, clusters, bases, means and
// coefficients in their stored precision.
#include <map>
#include <memory>
#include <string>

#include "model/model.h"

namespace acpca {

inline constexpr const char* kModelFormat = "adaptive-cpca model";
/// 2: one i8 scale per cluster basis; 3: no timing or memory figures (equal
/// inputs give equal bytes); 4: each pixel's world position (local lights);
/// 5: each pixel's normal and object (per-pixel labels); 6: the light set of
/// a captured transport; 7: the lamp samples and surfaces; 8: their tangents
/// and anisotropic materials. Versions 2 to 7 are read as well (without what
/// came later; version 2's compress_seconds and peak_memory_bytes are ignored).
inline constexpr int kModelVersion = 8;
inline constexpr int kOldestModelVersion = 2;

/// What a file written by ModelFileWriter holds: a whole model, or only
/// clusters (a streamed build keeps each finished tile so until it assembles
/// the model: no image header, no global basis).
enum class ModelFileKind { Whole, Clusters };

/// How many values a model's cluster arrays hold.
struct ModelSizes {
  long long clusters = 0, rows = 0, basisValues = 0, coefficients = 0;
  static ModelSizes of(const Model& m);
  ModelSizes& operator+=(const ModelSizes& o);
};

/// Writes a model file cluster by cluster: the image header and the global
/// basis first, then clusters appended in order until `sizes` are filled,
/// then the figures and the `complete` mark; atomically (temporary name,
/// renamed by finish()). Memory holds one append, so a streamed build never
/// holds the whole model; the file's layout is that of one written whole.
class ModelFileWriter {
 public:
  /// From `head`: geometry, method, settings, global basis, mean and
  /// precisions (its clusters are not written); `sizes`: of all appends.
  ModelFileWriter(const std::string& path, const Model& head, const ModelSizes& sizes,
                  ModelFileKind kind = ModelFileKind::Whole);
  ~ModelFileWriter();
  /// Appends the clusters of `clusters` (rows indexed in the whole image,
  /// offsets from 0, its precisions those of the head).
  void append(const Model& clusters);
  long long clustersWritten() const { return clusters_; }
  /// A whole float dataset beside the clusters (a tile's ground truth).
  void writeArray(const std::string& name, const std::vector<float>& values);
  /// sum over the clusters written of n_c (p_c + N), as Model::totalCost.
  double totalCost() const { return totalCost_; }
  /// Writes the figures of `summary` and `extra` attributes, marks the file
  /// complete and renames it into place.
  void finish(const Model& summary, const std::map<std::string, double>& extra = {});

 private:
  struct Datasets;
  std::string path_;
  int globalBases_ = 0;
  bool hasMean_ = false;
  CoeffPrecision precision_, basisPrecision_;
  long long clusters_ = 0, rows_ = 0;
  double totalCost_ = 0;
  std::unique_ptr<Datasets> data_;
};

/// Writes atomically (temporary name, renamed when complete).
void writeModel(const Model& model, const std::string& path);
/// The sizes a clusters-only file holds (without reading its arrays).
ModelSizes readModelClusterSizes(const std::string& path, int globalBases);
/// Reads a clusters-only file (ModelFileKind::Clusters) of a model with this
/// many global bases and these precisions; its `extra` attributes into extra.
Model readModelClusters(const std::string& path, const Model& head,
                        std::map<std::string, double>* extra);
/// Reads and validates a model file; throws UserError naming the file.
Model readModel(const std::string& path);
/// True if the file is an HDF5 file whose format attribute says model.
bool isModelFile(const std::string& path);

}  // namespace acpca
