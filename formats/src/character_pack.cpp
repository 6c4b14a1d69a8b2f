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

namespace {

// An impostor's or a cloth loop's clip and outfit ("": the bare body) must be the pack's.
void checkClipAndOutfit(const AnimationPack &body, const std::string &clip,
                        const std::string &outfit, const std::string &ctx) {
  const auto &clips = body.clips;
  if (std::none_of(clips.begin(), clips.end(), [&](const Clip &k) { return k.name == clip; }))
    throw Error(ctx + ", field 'clip': '" + clip + "' is not a clip of the pack");
  if (outfit.empty())
    return;
  const bool known =
      body.outfits && std::any_of(body.outfits->outfits.begin(), body.outfits->outfits.end(),
                                  [&](const auto &o) { return o.name == outfit; });
  if (!known)
    throw Error(ctx + ", field 'outfit': '" + outfit + "' is not an outfit of the pack");
}

} // namespace

CharacterPack loadCharacterPack(const Reader &reader) {
  CharacterPack p;
  p.body = loadAnimationPack(reader);
  for (size_t i = 0; i < reader.chunks().size(); ++i) {
    const ChunkEntry &c = reader.chunks()[i];
    const std::string ctx = chunkContext(reader, i);
    if (c.type == kImpostor) {
      Impostor m = decodeImpostor(reader.payload(c), c.version, ctx);
      checkClipAndOutfit(p.body, m.clip, m.outfit, ctx);
      if (p.impostor(m.clip, m.outfit))
        throw Error(ctx + ": a second impostor of clip '" + m.clip + "' and outfit '" + m.outfit +
                    "'");
      p.impostors.push_back(std::move(m));
    } else if (c.type == kCloth) {
      ClothLoop m = decodeClothLoop(reader.payload(c), ctx);
      checkClipAndOutfit(p.body, m.clip, m.outfit, ctx);
      clothVertexOf(p.body, m, ctx); // every loop vertex is a vertex of the mesh
      for (const auto &o : p.cloths)
        if (o.outfit == m.outfit && o.garment == m.garment && o.clip == m.clip)
          throw Error(ctx + ": a second loop of garment '" + m.garment + "' of outfit '" +
                      m.outfit + "' over clip '" + m.clip + "'");
      p.cloths.push_back(std::move(m));
    }
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
  for (const auto &m : p.cloths)
    w.add(kCloth, kClothVersion, encode(m));
  return w.bytes();
}

} // namespace crowd::pack
