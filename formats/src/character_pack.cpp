#include "crowd/formats/character_pack.h"

#include <algorithm>

#include "crowd/formats/error.h"
#include "crowd/formats/registry.h"

namespace crowd::pack {

const Impostor *CharacterPack::impostor(const std::string &clip, const std::string &outfit) const {
  for (const auto &m : impostors)
    if (m.clip == clip && m.outfit == outfit)
      return &m;
  return nullptr;
}

CharacterPack loadCharacterPack(const Reader &reader) {
  CharacterPack p;
  p.body = loadAnimationPack(reader);
  for (size_t i = 0; i < reader.chunks().size(); ++i) {
    const ChunkEntry &c = reader.chunks()[i];
    if (c.type != kImpostor)
      continue;
    const std::string ctx = chunkContext(reader, i);
    Impostor m = decodeImpostor(reader.payload(c), c.version, ctx);
    const auto &clips = p.body.clips;
    if (std::none_of(clips.begin(), clips.end(), [&](const Clip &k) { return k.name == m.clip; }))
      throw Error(ctx + ", field 'clip': '" + m.clip + "' is not a clip of the pack");
    if (!m.outfit.empty()) {
      const bool known = p.body.outfits &&
                         std::any_of(p.body.outfits->outfits.begin(), p.body.outfits->outfits.end(),
                                     [&](const auto &o) { return o.name == m.outfit; });
      if (!known)
        throw Error(ctx + ", field 'outfit': '" + m.outfit + "' is not an outfit of the pack");
    }
    if (p.impostor(m.clip, m.outfit))
      throw Error(ctx + ": a second impostor of clip '" + m.clip + "' and outfit '" + m.outfit +
                  "'");
    p.impostors.push_back(std::move(m));
  }
  return p;
}

std::vector<uint8_t> packBytes(const CharacterPack &p) {
  Reader body(packBytes(p.body), "body");
  Writer w;
  for (const auto &c : body.chunks()) {
    auto payload = body.payload(c);
    w.add(c.type, c.version, {payload.begin(), payload.end()});
  }
  for (const auto &m : p.impostors)
    w.add(kImpostor, kImpostorVersion, encode(m));
  return w.bytes();
}

} // namespace crowd::pack
