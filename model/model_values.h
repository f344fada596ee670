#pragma once
// What a model's values must satisfy before anything relights it: finite, and
// small enough that no relit value can overflow a float.
#include <string>

#include "model/model.h"

namespace acpca {

/// The largest relitBoundPerUnitLight a model file may have.
inline constexpr double kRelitBoundLimit = 1e20;

/// An upper bound on |relit value| per unit of the largest lattice light
/// value, from the triangle inequality on albedo_p * (u_p . W^T V_g^T L +
/// mu . V_g^T L): every value may be finite while their products overflow.
double relitBoundPerUnitLight(const Model& m);

/// UserError naming ctx on a non-finite basis, mean, coefficient or scale, or
/// values whose relit bound exceeds kRelitBoundLimit.
void checkModelValues(const Model& m, const std::string& ctx);

}  // namespace acpca
