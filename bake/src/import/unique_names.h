// Names the importer makes unique: joints are matched by name (an outfit to its body) and clips
// are chosen by name (--clip, a scene's agents), so two of one name would be one of them alone.
#pragma once
#include <set>
#include <string>
#include <vector>

namespace crowd::gltf {

// Renames every name that repeats an earlier one to NAME_2, NAME_3, ... (the first free), in
// order, so the same file always gives the same names. Returns how many were renamed.
inline size_t makeUnique(const std::vector<std::string *> &names) {
  std::set<std::string> taken;
  for (const std::string *name : names)
    taken.insert(*name);
  std::set<std::string> seen;
  size_t renamed = 0;
  for (std::string *name : names) {
    if (seen.insert(*name).second)
      continue;
    std::string fresh;
    for (int k = 2; fresh.empty() || taken.count(fresh); ++k)
      fresh = *name + "_" + std::to_string(k);
    taken.insert(fresh);
    seen.insert(fresh);
    *name = fresh;
    ++renamed;
  }
  return renamed;
}

} // namespace crowd::gltf
