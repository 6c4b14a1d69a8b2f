#include "crowd/support/json_checker.h"

#include <algorithm>
#include <cctype>
#include <cstdio>

#include "crowd/formats/error.h"

namespace crowd::support {

using nlohmann::json;

void checkJsonDepth(std::string_view text, const std::string &path, int limit) {
  int depth = 0;
  bool inString = false;
  for (size_t i = 0; i < text.size(); ++i) {
    const char c = text[i];
    if (inString) {
      if (c == '\\')
        ++i;
      else if (c == '"')
        inString = false;
    } else if (c == '"') {
      inString = true;
    } else if (c == '[' || c == '{') {
      if (++depth > limit)
        throw Error(path + ":" + lineColumn(std::string(text.substr(0, i + 1)), i) +
                    ": JSON nests deeper than " + std::to_string(limit) + " levels");
    } else if (c == ']' || c == '}') {
      --depth;
    }
  }
}

std::string lineColumn(const std::string &text, size_t offset) {
  size_t line = 1, col = 1;
  for (size_t i = 0; i < offset && i < text.size(); ++i) {
    if (text[i] == '\n') {
      ++line;
      col = 1;
    } else {
      ++col;
    }
  }
  return std::to_string(line) + ":" + std::to_string(col);
}

json JsonChecker::parse() const {
  checkJsonDepth(text_, path_);
  try {
    return json::parse(text_);
  } catch (const json::parse_error &e) {
    std::string what = e.what();
    if (auto p = what.find("syntax error"); p != std::string::npos)
      what = what.substr(p);
    throw Error(path_ + ":" + lineColumn(text_, e.byte ? e.byte - 1 : 0) + ": " + what);
  } catch (const json::out_of_range &e) {
    // A number past a double's range (1e400): the parser names the number, not where it is.
    std::string what = e.what();
    const size_t open = what.find('\''), close = what.rfind('\'');
    const std::string number =
        open != std::string::npos && close > open ? what.substr(open + 1, close - open - 1) : "";
    const size_t at = number.empty() ? std::string::npos : text_.find(number);
    throw Error(
        path_ + (at == std::string::npos ? "" : ":" + lineColumn(text_, at)) +
        ": a number out of range" +
        (number.empty() ? "" : ": " + number.substr(0, 40) + (number.size() > 40 ? "..." : "")));
  }
}

namespace {

// Where element `index` of the array whose key starts at `key` begins, or npos.
size_t elementStart(const std::string &text, size_t key, size_t index) {
  size_t i = text.find(':', text.find('"', key + 1));
  i = i == std::string::npos ? i : text.find_first_not_of(" \t\r\n", i + 1);
  if (i == std::string::npos || text[i] != '[')
    return std::string::npos;
  int depth = 0;
  bool inString = false;
  for (size_t n = 0, j = i + 1; j < text.size(); ++j) {
    const char c = text[j];
    if (inString) {
      j += c == '\\';
      inString = c != '"';
    } else if (c == '"' || c == '[' || c == '{' || c == ',' || c == ']' || c == '}') {
      if (depth == 0 && c != ',' && c != ']' && c != '}' && n == index)
        return j;
      inString = c == '"';
      depth += c == '[' || c == '{';
      depth -= c == ']' || c == '}';
      if (depth < 0)
        return std::string::npos;
      n += depth == 0 && c == ',';
    } else if (depth == 0 && n == index && !std::isspace(static_cast<unsigned char>(c))) {
      return j; // a number, true, false or null
    }
  }
  return std::string::npos;
}

} // namespace

void JsonChecker::fail(const Keys &keys, const std::string &what) const {
  size_t pos = 0;
  for (const auto &k : keys) {
    // An all-digit key after an array's key is an element index; otherwise a key to find.
    const bool index = !k.empty() && std::all_of(k.begin(), k.end(), ::isdigit);
    size_t found = index ? elementStart(text_, pos, std::stoul(k)) : std::string::npos;
    if (found == std::string::npos)
      found = text_.find("\"" + k + "\"", pos);
    if (found == std::string::npos)
      break;
    pos = found;
  }
  std::string where;
  for (const auto &k : keys)
    where += "/" + k;
  throw Error(path_ + ":" + lineColumn(text_, pos) + ": " + (where.empty() ? "" : where + ": ") +
              what);
}

void JsonChecker::onlyKeys(const json &j, const Keys &keys, const Keys &allowed) const {
  if (!j.is_object())
    fail(keys, "expected an object");
  for (auto it = j.begin(); it != j.end(); ++it)
    if (std::find(allowed.begin(), allowed.end(), it.key()) == allowed.end()) {
      auto k = keys;
      k.push_back(it.key());
      std::string list;
      for (const auto &a : allowed)
        list += (list.empty() ? "" : ", ") + a;
      fail(k, "unknown key '" + it.key() + "' (known: " + list + ")");
    }
}

double JsonChecker::number(const json &j, const Keys &keys, double lo, double hi) const {
  if (!j.is_number())
    fail(keys, "expected a number");
  double v = j.get<double>();
  if (!(v >= lo && v <= hi)) {
    char text[96];
    std::snprintf(text, sizeof text, "value %.9g is outside [%.9g, %.9g]", v, lo, hi);
    fail(keys, text);
  }
  return v;
}

std::string JsonChecker::string(const json &j, const Keys &keys) const {
  if (!j.is_string() || j.get<std::string>().empty())
    fail(keys, "expected a non-empty string");
  return j.get<std::string>();
}

bool JsonChecker::boolean(const json &j, const Keys &keys) const {
  if (!j.is_boolean())
    fail(keys, "expected true or false");
  return j.get<bool>();
}

} // namespace crowd::support
