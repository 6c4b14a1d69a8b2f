#include "crowd/runtime/preview_scene.h"

#include <algorithm>
#include <cmath>
#include <filesystem>

#include "crowd/formats/error.h"
#include "crowd/runtime/impostor_runtime.h"

namespace crowd::runtime {

Scene previewScene(const std::string &packPath, const pack::CharacterPack &p,
                   const PreviewChoice &choice) {
  Scene s;
  s.path = packPath;
  s.packPaths = {packPath};
  s.packNames = {std::filesystem::path(packPath).stem().string()};
  s.impostorPaths = {""};
  for (const auto &c : p.body.clips)
    s.clipNames.push_back(c.name);
  if (s.clipNames.empty())
    s.clipNames = {""};
  s.outfitNames.clear();
  if (p.body.outfits)
    for (const auto &o : p.body.outfits->outfits)
      s.outfitNames.push_back(o.name);
  if (s.outfitNames.empty())
    s.outfitNames = {""};
  s.palettes = {{}};
  const auto &sphere = p.body.mesh.boundingSphere;
  const double r = std::max(1e-3, double(sphere[3]));
  auto chosen = [&](int pick, size_t count, const char *what) {
    if (pick < -1 || pick >= int(count))
      throw Error(packPath + ": no " + what + " " + std::to_string(pick) + " (the pack has " +
                  std::to_string(count) + ")");
    std::vector<uint32_t> ids;
    for (uint32_t k = 0; k < count; ++k)
      if (pick < 0 || int(k) == pick)
        ids.push_back(k);
    return ids;
  };
  const auto clips = chosen(choice.clip, s.clipNames.size(), "clip");
  const auto outfits = chosen(choice.outfit, s.outfitNames.size(), "outfit");
  const size_t pairs = clips.size() * outfits.size();
  const double spacing = 2.2 * r, width = spacing * double(pairs);
  // The far row sits past where every impostor takes over (a texel per pixel at 1080 rows).
  double far = 40 * r;
  for (const auto &m : p.impostors)
    far = std::max(far,
                   1.5 * oneToOneDistance(m, s.camera.fovYDegrees * 3.14159265358979 / 180, 1080));
  for (int row = 0; row < 2; ++row)
    for (size_t k = 0; k < pairs; ++k) {
      Instance inst;
      inst.clip = clips[k / outfits.size()];
      inst.outfit = outfits[k % outfits.size()];
      inst.position = {(double(k) + 0.5) * spacing - width / 2 - sphere[0], -sphere[1] + r,
                       row == 0 ? -sphere[2] : -far};
      s.instances.push_back(inst);
    }
  const double halfFov = s.camera.fovYDegrees * 0.5 * 3.14159265358979 / 180;
  const double distance = std::max(width / 2 / std::tan(halfFov) / 1.6, 3 * r);
  s.camera.position = {0, 1.3 * r, distance};
  s.camera.target = {0, r, 0};
  // A turntable: once around the row in 24 s, starting in front of it.
  const int keys = 48;
  for (int k = 0; k <= keys; ++k) {
    const double a = 2 * 3.14159265358979 * k / keys;
    s.camera.path.push_back(
        {24.0 * k / keys, {distance * std::sin(a), 1.3 * r, distance * std::cos(a)}, {0, r, 0}});
  }
  s.camera.farPlane = std::max(1000.0, 4 * (far + distance));
  s.camera.nearPlane = std::max(1e-3, r * 0.01);
  return s;
}

void crossfadeFrom(Scene &next, const PreviewChoice &previous, const PreviewChoice &chosen,
                   double now, double seconds) {
  if (previous.clip < 0 || chosen.clip < 0 || previous.clip == chosen.clip ||
      previous.outfit != chosen.outfit)
    return;
  for (auto &inst : next.instances)
    inst.fade = {previous.clip, inst.timeOffset, now, seconds};
}

} // namespace crowd::runtime
