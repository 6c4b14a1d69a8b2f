// crowd::Error: the one exception type every layer throws, carrying file/field context in its
// message.
#pragma once
#include <stdexcept>
#include <string>
#include <vector>

namespace crowd {

class Error : public std::runtime_error {
public:
  explicit Error(const std::string &message) : std::runtime_error(message) {}
};

// The one wording for an unknown name: "no clip named 'dance' (clips: walk, run, idle)", or
// "(clips: none)" when there is none.
inline Error unknownName(const std::string &kind, const std::string &name,
                         const std::vector<std::string> &known) {
  std::string list;
  for (const auto &k : known)
    list.append(list.empty() ? "" : ", ").append(k);
  std::string text = "no ";
  text.append(kind).append(" named '").append(name).append("' (").append(kind).append("s: ");
  return Error(text.append(list.empty() ? "none" : list).append(")"));
}

} // namespace crowd
