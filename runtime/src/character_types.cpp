#include "crowd/runtime/character_types.h"

namespace crowd::runtime {

CharacterTypes characterTypes(Scene &scene, const std::vector<pack::CharacterPack> &packs,
                              const std::vector<const pack::Impostor *> &sceneImpostors) {
  CharacterTypes t;
  for (const auto &p : packs) {
    t.packs.push_back(&p.body);
    t.impostors.push_back(nullptr);
    t.cloths.push_back(p.cloths);
  }
  for (size_t k = 0; k < packs.size(); ++k) {
    if (k < sceneImpostors.size() && sceneImpostors[k]) {
      t.impostors[k] = sceneImpostors[k];
      continue;
    }
    const auto &p = packs[k];
    // The type of each (clip, outfit) impostor: the pack's own slot for the first, new ones after.
    std::vector<uint32_t> typeOf;
    for (size_t i = 0; i < p.impostors.size(); ++i) {
      if (i == 0) {
        typeOf.push_back(uint32_t(k));
        t.impostors[k] = &p.impostors[0];
        continue;
      }
      typeOf.push_back(uint32_t(t.packs.size()));
      t.packs.push_back(&p.body);
      t.impostors.push_back(&p.impostors[i]);
      t.cloths.push_back(p.cloths);
      scene.packNames.push_back(scene.packNames[k] + " (" + p.impostors[i].clip +
                                (p.impostors[i].outfit.empty() ? "" : "/" + p.impostors[i].outfit) +
                                ")");
    }
    for (auto &inst : scene.instances) {
      if (inst.pack != k || p.impostors.empty())
        continue;
      const std::string &clipName = scene.clipNames[inst.clip];
      const std::string clip = clipName.empty() ? p.body.clips.at(0).name : clipName;
      std::string outfit = scene.outfitNames[inst.outfit];
      if (outfit.empty() && p.body.outfits && !p.body.outfits->outfits.empty())
        outfit = p.body.outfits->outfits[0].name; // "" is the pack's first outfit
      for (size_t i = 0; i < p.impostors.size(); ++i)
        if (p.impostors[i].clip == clip &&
            (p.impostors[i].outfit.empty() || p.impostors[i].outfit == outfit)) {
          inst.pack = typeOf[i];
          break;
        }
    }
  }
  return t;
}

} // namespace crowd::runtime
