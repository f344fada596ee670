#pragma once
// The plain, slow relight of a model, straight from its definition in double:
// the yardstick the fast ModelRelighter is tested against.
#include <vector>

#include "model/model.h"

namespace acpca {

/// Per-row RGB (albedo applied) for each lighting: the plain reference relight
/// of a model (the fast relighter must match it).
std::vector<std::vector<float>> relightModelReference(
    const Model& model, const std::vector<std::vector<double>>& lightings);
}  // namespace acpca
