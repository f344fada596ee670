#include "viewer/viewer_script.h"

#include <fstream>
#include <sstream>

#include "core/error.h"
#include "lighting/local_light.h"
#include "lighting/spec_parsing.h"

namespace acpca {

namespace {

int keyCode(const std::string& word, const std::string& where) {
  if (word == "esc") return 27;
  if (word == "space") return ' ';
  if (word == "tab") return '\t';
  if (word.size() == 1) return static_cast<unsigned char>(word[0]);
  throw UserError(concat(where, ": key '", word, "' is not one character, esc, space or tab"));
}

}  // namespace

std::vector<ScriptEvent> readViewerScript(const std::string& path) {
  std::ifstream in(path);
  if (!in) throw ParameterError("viewer script", path, "cannot open the file");
  std::vector<ScriptEvent> events;
  std::string line;
  for (int number = 1; std::getline(in, line); ++number) {
    std::istringstream words(line);
    std::string verb;
    if (!(words >> verb) || verb[0] == '#') continue;
    std::vector<std::string> args;
    for (std::string w; words >> w;) args.push_back(w);
    const std::string where = concat(path, ":", number);
    auto need = [&](size_t count) {
      if (args.size() != count)
        throw UserError(concat(where, ": '", verb, "' takes ", count, " argument(s)"));
    };
    auto numberAt = [&](size_t i) { return parseFiniteNumber(args[i], where, verb); };
    ScriptEvent e{ScriptEvent::Kind::Wait};
    if (verb == "key") {
      need(1);
      e = {ScriptEvent::Kind::Key, double(keyCode(args[0], where))};
    } else if (verb == "drag") {
      need(2);
      e = {ScriptEvent::Kind::Drag, numberAt(0), numberAt(1)};
    } else if (verb == "dragfrom") {
      need(4);
      e = {ScriptEvent::Kind::DragFrom, numberAt(0), numberAt(1)};
      e.c = numberAt(2), e.d = numberAt(3);
    } else if (verb == "press") {
      need(2);
      e = {ScriptEvent::Kind::Press, numberAt(0), numberAt(1)};
    } else if (verb == "release") {
      need(0);
      e = {ScriptEvent::Kind::Release};
    } else if (verb == "wheel") {
      need(1);
      e = {ScriptEvent::Kind::Wheel, numberAt(0)};
    } else if (verb == "light") {
      need(1);
      e = {ScriptEvent::Kind::Light, 0, 0, args[0]};
      try {
        e.light = parseLocalLight(args[0]);  // refused here, with the line, rather than mid-run
      } catch (const UserError& error) {
        throw UserError(concat(where, ": ", error.what()));
      }
    } else if (verb == "rotate") {
      need(1);
      const auto comma = args[0].find(',');
      e = {ScriptEvent::Kind::Rotate, parseFiniteNumber(args[0].substr(0, comma), where, "rotate"),
           comma == std::string::npos
               ? 0.0
               : parseFiniteNumber(args[0].substr(comma + 1), where, "rotate")};
    } else if (verb == "exposure") {
      need(1);
      e = {ScriptEvent::Kind::Exposure, numberAt(0)};
    } else if (verb == "rank") {
      need(1);
      e = {ScriptEvent::Kind::Rank, numberAt(0)};
      if (e.a < 0 || e.a > 100) throw UserError(concat(where, ": rank is a percentage, 0..100"));
    } else if (verb == "env") {
      need(1);
      e = {ScriptEvent::Kind::Env, numberAt(0)};
    } else if (verb == "save" || verb == "screenshot") {
      need(1);
      e = {verb == "save" ? ScriptEvent::Kind::Save : ScriptEvent::Kind::Screenshot, 0, 0, args[0]};
    } else if (verb == "wait") {
      need(1);
      e = {ScriptEvent::Kind::Wait, numberAt(0)};
      if (e.a < 0) throw UserError(concat(where, ": wait takes milliseconds >= 0"));
    } else {
      throw UserError(concat(where, ": unknown event '", verb,
                             "' (key, drag, dragfrom, press, release, wheel, light, rotate, "
                             "exposure, rank, env, "
                             "save, screenshot, wait)"));
    }
    events.push_back(e);
  }
  return events;
}

}  // namespace acpca
