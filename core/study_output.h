#pragma once
// What a study or benchmark of this library hands back besides the files it
// writes: its figures as JSON and a summary for a person, which the front end
// prints or saves as it likes. Progress lines go to a log callback.
#include <functional>
#include <nlohmann/json.hpp>
#include <string>

namespace acpca {

using StudyLog = std::function<void(const std::string&)>;

struct StudyOutput {
  nlohmann::json json;
  std::string summary;  ///< Markdown or plain text
};

}  // namespace acpca
