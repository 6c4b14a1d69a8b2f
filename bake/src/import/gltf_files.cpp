#include <algorithm>
#include <cctype>
#include <cstring>

#include <nlohmann/json.hpp>

#include "crowd/bake/import.h"
#include "crowd/support/json_checker.h"
#include "gltf_schema.h"

namespace crowd {

// A URI as tinygltf reads it: percent-decoded, "./" dropped.
std::string uriAsRead(const std::string &uri) {
  std::string out;
  for (size_t i = 0; i < uri.size(); ++i) {
    if (uri[i] == '%' && i + 2 < uri.size() && std::isxdigit(uint8_t(uri[i + 1])) &&
        std::isxdigit(uint8_t(uri[i + 2]))) {
      out += char(std::stoi(uri.substr(i + 1, 2), nullptr, 16));
      i += 2;
    } else {
      out += uri[i];
    }
  }
  return out.rfind("./", 0) == 0 ? out.substr(2) : out;
}

std::vector<std::string> gltfFiles(const std::string &path, const InputPolicy &policy) {
  std::vector<std::string> files;
  auto add = [&](const std::string &file) {
    checkInputFile(file, policy); // a missing or special file is the import's to report
    if (std::find(files.begin(), files.end(), file) == files.end())
      files.push_back(file);
  };
  try {
    add(path);
    const std::vector<uint8_t> bytes = readInputFile(path, policy);
    std::string_view json(reinterpret_cast<const char *>(bytes.data()), bytes.size());
    if (bytes.size() >= 20 && std::memcmp(bytes.data(), "glTF", 4) == 0) {
      uint32_t length = 0;
      std::memcpy(&length, bytes.data() + 12, 4);
      json = json.substr(20, length);
    }
    support::checkJsonDepth(json, path);
    const auto j = nlohmann::json::parse(json);
    for (const char *array : {"buffers", "images"}) {
      if (!j.contains(array) || !j[array].is_array())
        continue;
      for (const auto &item : j[array]) {
        if (!item.is_object() || !item.contains("uri") || !item["uri"].is_string())
          continue;
        const std::string uri = item["uri"];
        if (uri.rfind("data:", 0) != 0)
          add(resolveNamedInput(uriAsRead(uri), path, policy, "URI"));
      }
    }
  } catch (const std::exception &) {
    // The import reads the file again and reports what is wrong with it.
  }
  return files;
}

} // namespace crowd
