#pragma once
// Scripted input for `view --script FILE`: the events a user would produce,
// one per line, so that tests and demos can drive the window without a person.
//   key C            a key press: one character, or esc / space / tab
//   drag DX DY       a left-button drag by DX, DY pixels (of the lighting)
//   dragfrom X Y DX DY   a drag that starts at pixel X, Y: of the light drawn
//                    there, if any, else of the lighting
//   press X Y        the left button pressed at pixel X, Y: on a drawn light it
//                    is held (sphere lamps lit as points, viewer/view_input.h
//                    previewLights) and each drag moves it, until
//   release          the button let go: the frame at full quality
//                    (a press off any light holds the map: drags and
//                    rotates until the release light its sources as points)
//   wheel N          N notches of the wheel (> 0 moves the selected light nearer)
//   light SPEC       add a local light (relight's --light grammar), selected
//   rotate YAW[,PITCH]   set the lighting's rotation in degrees
//   exposure EV | rank PERCENT | env INDEX (0-based)   as the trackbars do
//   save STEM        write STEM.exr and STEM.png of the current frame
//   screenshot FILE  write the window's canvas (image and status strip) as PNG
//   wait MS          keep the window up for MS milliseconds
// Blank lines and lines starting with # are skipped.
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "lighting/local_light.h"

namespace acpca {

struct ScriptEvent {
  enum class Kind {
    Key,
    Drag,
    DragFrom,
    Press,
    Release,
    Wheel,
    Light,
    Rotate,
    Exposure,
    Rank,
    Env,
    Save,
    Screenshot,
    Wait
  };
  ScriptEvent(Kind kind, double a = 0, double b = 0, std::string path = {})
      : kind(kind), a(a), b(b), path(std::move(path)) {}
  Kind kind;
  double a, b;                      ///< numbers (key code in a for Key)
  double c = 0, d = 0;              ///< DragFrom: the drag (a, b: where it starts)
  std::string path;                 ///< Save, Screenshot; Light: the spec
  std::optional<LocalLight> light;  ///< Light: the spec, parsed once as the script is read
};

/// Reads a script; throws UserError naming the file and line of anything wrong.
std::vector<ScriptEvent> readViewerScript(const std::string& path);

}  // namespace acpca
