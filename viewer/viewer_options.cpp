#include <algorithm>

#include "core/error.h"
#include "model/model_file.h"
#include "viewer/viewer.h"

namespace acpca {

ViewState parseViewerRotation(const std::string& text, ViewState view) {
  // "YAW,PITCH" is short for "YAW,PITCH,0": the viewer turns yaw and pitch only.
  const bool twoAngles = std::count(text.begin(), text.end(), ',') == 1;
  const auto rotations = parseRotationSpec(twoAngles ? text + ",0" : text);
  if (rotations.size() != 1 || rotations[0].roll != 0)
    throw ParameterError("rotation", text, "give one YAW[,PITCH] for the viewer");
  view.yaw = rotations[0].yaw;
  view.pitch = rotations[0].pitch;
  return view;
}

void validateViewerOptions(const ViewerOptions& o) {
  if (o.background == Background::Alpha)
    throw ParameterError("background", "alpha", "the viewer shows env or black");
  if (o.initial.rankPercent < 0 || o.initial.rankPercent > 100)
    throw ParameterError("rank percent", o.initial.rankPercent, "give 0..100");
  if (o.frames < 0) throw ParameterError("frames", o.frames, "must be >= 0");
  if (o.envSpecs.empty()) throw ParameterError("environment", "", "give at least one lighting");
  if (!isModelFile(o.modelPath))
    throw UserError(concat("'", o.modelPath,
                           "' is not a model file: the viewer relights models (compress makes "
                           "one); a dense transport is too slow to turn interactively"));
}

}  // namespace acpca
