// crowd::Error: the one exception type every layer throws, carrying file/field context in its
// message.
#pragma once
#include <stdexcept>
#include <string>

namespace crowd {

class Error : public std::runtime_error {
public:
  explicit Error(const std::string &message) : std::runtime_error(message) {}
};

} // namespace crowd
