#include "crowd/formats/registry.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstring>

#include "crowd/formats/character_pack.h"
#include "crowd/formats/chunks.h"
#include "crowd/formats/cloth.h"
#include "crowd/formats/error.h"
#include "crowd/formats/impostor.h"
#include "crowd/formats/terrain.h"

namespace crowd::pack {

Value text(std::string s) { return {std::move(s), false}; }

Value number(double v) {
  char b[32];
  if (std::isfinite(v) && v == std::floor(v) && std::fabs(v) < 1e15)
    std::snprintf(b, sizeof b, "%lld", static_cast<long long>(v));
  else
    std::snprintf(b, sizeof b, "%.7g", v);
  return {b, std::isfinite(v)};
}

namespace {

Value yesNo(bool b) { return {b ? "true" : "false", true}; }
// Appends `word` to a list separated by `separator`.
void appendWord(std::string &list, const std::string &word, char separator = ' ') {
  if (!list.empty())
    list += separator;
  list += word;
}

std::string size2(uint32_t w, uint32_t h) { return std::to_string(w) + "x" + std::to_string(h); }

Description describeProvenance(std::span<const uint8_t> b, uint32_t, const std::string &ctx) {
  Provenance p = decodeProvenance(b, ctx);
  Description d;
  d.add("baker", text(p.bakerVersion));
  Description::Table settings{"settings", {"key", "value"}, {}};
  for (const auto &[k, v] : p.settings)
    settings.rows.push_back({text(k), text(v)});
  Description::Table inputs{"inputs", {"file", "bytes", "hash"}, {}};
  for (const auto &in : p.inputs)
    inputs.rows.push_back({text(in.path), number(double(in.size)), text(in.hash)});
  d.tables = {settings, inputs};
  return d;
}

Description describeSkeleton(std::span<const uint8_t> b, uint32_t, const std::string &ctx) {
  Skeleton s = decodeSkeleton(b, ctx);
  Description d;
  Description::Table joints{"joints", {"index", "name", "parent"}, {}};
  for (size_t i = 0; i < s.jointCount(); ++i)
    joints.rows.push_back({number(double(i)), text(s.names[i]), number(s.parents[i])});
  d.tables = {joints};
  return d;
}

Description describeClips(std::span<const uint8_t> b, uint32_t, const std::string &ctx) {
  Description d;
  Description::Table clips{
      "clips", {"name", "frames", "fps", "start_time", "first_frame", "loop"}, {}};
  for (const auto &c : decodeClips(b, ctx))
    clips.rows.push_back({text(c.name), number(c.frameCount), number(c.fps), number(c.startTime),
                          number(c.firstFrame), yesNo(c.loop)});
  d.tables = {clips};
  return d;
}

Description describeAnimation(std::span<const uint8_t> b, uint32_t, const std::string &ctx) {
  AnimationTexture t = decodeAnimationTexture(b, ctx);
  Description d;
  d.add("encoding", text(name(t.encoding)))
      .add("format", text(name(t.format)))
      .add("size", text(size2(t.width, t.height)))
      .add("joints", number(t.jointCount))
      .add("frames", number(t.frameCount))
      .add("frames_per_row", number(t.framesPerRow))
      .add("bytes_per_joint_per_frame",
           number(double(t.frameTexels()) * bytesPerTexel(t.format) / t.jointCount))
      .add("texel_bytes", number(double(t.texels.size())));
  if (!t.matrixJoints.empty())
    d.add("matrix_joints", number(double(t.matrixJoints.size())));
  return d;
}

std::vector<Image> imagesAnimation(std::span<const uint8_t> b, uint32_t, const std::string &ctx) {
  AnimationTexture t = decodeAnimationTexture(b, ctx);
  return {{"animation", t.width, t.height, 4,
           t.format == TexelFormat::RGBA32F ? Image::Pixel::F32 : Image::Pixel::F16,
           std::move(t.texels)}};
}

Description describeSkin(std::span<const uint8_t> b, uint32_t, const std::string &ctx) {
  SkinTexture s = decodeSkinTexture(b, ctx);
  Description d;
  d.add("format", text("rgba32f"))
      .add("size", text(size2(s.width, s.height)))
      .add("vertices", number(s.vertexCount));
  return d;
}

std::vector<Image> imagesSkin(std::span<const uint8_t> b, uint32_t, const std::string &ctx) {
  SkinTexture s = decodeSkinTexture(b, ctx);
  Image image{"skin", s.width, s.height, 4, Image::Pixel::F32, {}};
  image.bytes.resize(s.texels.size() * 4);
  std::memcpy(image.bytes.data(), s.texels.data(), image.bytes.size());
  return {image};
}

Description describeMesh(std::span<const uint8_t> b, uint32_t, const std::string &ctx) {
  Mesh m = decodeMesh(b, ctx);
  Description d;
  const auto &s = m.boundingSphere;
  d.add("vertices", number(double(m.vertexCount())))
      .add("triangles", number(double(m.indices.size() / 3)))
      .add("uvs", yesNo(!m.uvs.empty()))
      .add("bounding_sphere", text("centre (" + number(s[0]).text + ", " + number(s[1]).text +
                                   ", " + number(s[2]).text + ") radius " + number(s[3]).text));
  Description::Table subs{"sub_meshes", {"name", "first_index", "triangles"}, {}};
  for (const auto &sm : m.subMeshes)
    subs.rows.push_back({text(sm.name), number(sm.firstIndex), number(sm.indexCount / 3)});
  d.tables = {subs};
  return d;
}

Description describeTexture(std::span<const uint8_t> b, uint32_t, const std::string &ctx) {
  Texture t = decodeTexture(b, ctx);
  Description d;
  d.add("format", text("rgba8")).add("size", text(size2(t.width, t.height)));
  return d;
}

std::vector<Image> imagesTexture(std::span<const uint8_t> b, uint32_t, const std::string &ctx) {
  Texture t = decodeTexture(b, ctx);
  return {{"diffuse", t.width, t.height, 4, Image::Pixel::U8, std::move(t.rgba)}};
}

Description describeLod(std::span<const uint8_t> b, uint32_t, const std::string &ctx) {
  Lod l = decodeLod(b, ctx);
  const uint32_t n = uint32_t(l.collapse.size());
  Description d;
  d.add("vertices", number(n))
      .add("triangles", number(double(l.totalTriangles(n))))
      .add("floor_vertices", number(l.floorVertices))
      .add("floor_triangles", number(double(l.totalTriangles(l.floorVertices))))
      .add("sub_meshes", number(double(l.triangleCounts.size() / (n + 1))));
  return d;
}

Description describeOutfits(std::span<const uint8_t> b, uint32_t, const std::string &ctx) {
  Outfits o = decodeOutfits(b, ctx);
  Description d;
  d.add("body_sub_meshes", number(o.bodySubMeshes));
  Description::Table outfits{"outfits", {"name", "draws", "coverage"}, {}};
  for (const auto &outfit : o.outfits) {
    std::string draws, coverage;
    for (uint32_t s : outfit.subMeshes)
      appendWord(draws, std::to_string(s), ',');
    for (Coverage c : outfit.coverage)
      appendWord(coverage, name(c), ',');
    outfits.rows.push_back({text(outfit.name), text(draws), text(coverage)});
  }
  d.tables = {outfits};
  return d;
}

Description describeLooks(std::span<const uint8_t> b, uint32_t, const std::string &ctx) {
  Looks l = decodeLooks(b, ctx);
  Description d;
  Description::Table looks{"looks", {"sub_mesh", "colour", "textured"}, {}};
  for (size_t s = 0; s < l.textured.size(); ++s) {
    std::string colour;
    for (int k = 0; k < 4; ++k) {
      char buf[16];
      std::snprintf(buf, sizeof buf, "%.3g", double(l.colours[4 * s + size_t(k)]));
      appendWord(colour, buf, ',');
    }
    looks.rows.push_back({number(double(s)), text(colour), text(l.textured[s] ? "yes" : "no")});
  }
  d.tables = {looks};
  return d;
}

const char *timeTableName(const std::vector<float> &times) {
  switch (timeTable(times)) {
  case TimeTable::Step:
    return "uniform";
  case TimeTable::Ticks:
    return "ticks";
  default:
    return "keys";
  }
}

Description describeJointTracks(std::span<const uint8_t> b, uint32_t version,
                                const std::string &ctx) {
  const JointTracks t = decodeJointTracks(b, ctx, version);
  Description d;
  d.add("nodes", number(double(t.skeleton.nodeCount())))
      .add("joints", number(double(t.skeleton.jointNodes.size())))
      .add("skeleton_bytes", number(double(skeletonBytes(t.skeleton))));
  Description::Table clips{
      "track_clips",
      {"clip", "samples", "time_table", "default", "constant", "animated", "mean_bits", "bytes"},
      {}};
  for (const TrackClip &c : t.clips) {
    size_t kinds[3] = {0, 0, 0};
    double bits = 0;
    for (const Track &track : c.tracks) {
      ++kinds[size_t(track.kind)];
      bits += track.bits;
    }
    clips.rows.push_back(
        {text(c.name), number(double(c.times.size())), text(timeTableName(c.times)),
         number(double(kinds[0])), number(double(kinds[1])), number(double(kinds[2])),
         number(kinds[2] ? bits / double(kinds[2]) : 0), number(double(clipBytes(c)))});
  }
  d.tables = {clips};
  return d;
}

Description describeSourceMap(std::span<const uint8_t> b, uint32_t, const std::string &ctx) {
  SourceMap m = decodeSourceMap(b, ctx);
  const auto made = std::count(m.ordinals.begin(), m.ordinals.end(), SourceMap::kMade);
  Description d;
  d.add("vertices", number(double(m.vertexCount())))
      .add("runs", number(double(m.runs.size())))
      .add("per_vertex_ordinals", yesNo(!m.ordinals.empty()))
      .add("made_by_bake", number(double(made)));
  return d;
}

Description describeMorphs(std::span<const uint8_t> b, uint32_t, const std::string &ctx) {
  Morphs m = decodeMorphs(b, ctx);
  uint32_t mostActive = 0;
  for (uint32_t f = 0; f < m.frameCount(); ++f) {
    uint32_t active = 0;
    for (uint32_t s = 0; s < kMorphSlots; ++s)
      active += m.slots[size_t(f) * kMorphSlots + s].weight != 0;
    mostActive = std::max(mostActive, active);
  }
  Description d;
  d.add("targets", number(double(m.targets.size())))
      .add("frames", number(m.frameCount()))
      .add("offset_vertices", number(double(m.offsets.size() / 8)))
      .add("most_active_in_a_frame", number(mostActive));
  return d;
}

Description describeCloth(std::span<const uint8_t> b, uint32_t, const std::string &ctx) {
  ClothLoop c = decodeClothLoop(b, ctx);
  const double largestStep = std::max({c.step[0], c.step[1], c.step[2]});
  Description d;
  d.add("outfit", text(c.outfit))
      .add("garment", text(c.garment))
      .add("clip", text(c.clip))
      .add("vertices", number(c.vertexCount()))
      .add("frames", number(c.frameCount()))
      .add("fps", number(c.fps))
      .add("cycles", number(c.cycles))
      .add("cache_start", number(c.cacheStart))
      .add("blend_frames", number(c.blendFrames))
      .add("quantisation_step", number(largestStep));
  return d;
}

Description describeTerrain(std::span<const uint8_t> b, uint32_t, const std::string &ctx) {
  Terrain t = decodeTerrain(b, ctx);
  size_t counts[3] = {0, 0, 0}, shadowed = 0;
  for (size_t i = 0; i < t.cells(); ++i) {
    ++counts[t.ground[i]];
    shadowed += t.ground[i] == uint8_t(Ground::Walkable) && t.shadowHeights[i] > t.heights[i];
  }
  char light[64];
  std::snprintf(light, sizeof light, "%.4g,%.4g,%.4g", t.light[0], t.light[1], t.light[2]);
  Description d;
  d.add("cells", text(size2(t.width, t.depth)))
      .add("cell", number(t.cell))
      .add("origin", text(number(t.originX).text + "," + number(t.originZ).text))
      .add("walkable_cells", number(double(counts[2])))
      .add("blocked_cells", number(double(counts[1])))
      .add("empty_cells", number(double(counts[0])))
      .add("walkable_cells_in_shadow", number(double(shadowed)))
      .add("light", text(light))
      .add("step_height", number(t.stepHeight))
      .add("max_slope_deg", number(t.maxSlopeDeg))
      .add("mesh_vertices", number(double(t.positions.size() / 3)))
      .add("mesh_triangles", number(double(t.indices.size() / 3)));
  return d;
}

// The maps as images, row 0 at the lowest z: heights and shadow heights as floats, and the
// ground codes scaled to 0 / 127 / 254 so that a viewer shows them.
std::vector<Image> imagesTerrain(std::span<const uint8_t> b, uint32_t, const std::string &ctx) {
  Terrain t = decodeTerrain(b, ctx);
  auto floats = [&](const char *name, const std::vector<float> &v) {
    Image image{name, t.width, t.depth, 1, Image::Pixel::F32, {}};
    image.bytes.resize(v.size() * sizeof(float));
    std::memcpy(image.bytes.data(), v.data(), image.bytes.size());
    return image;
  };
  Image ground{"walkable", t.width, t.depth, 1, Image::Pixel::U8, t.ground};
  for (auto &g : ground.bytes)
    g = uint8_t(g * 127);
  return {floats("heights", t.heights), ground, floats("shadow_heights", t.shadowHeights)};
}

Description describeImpostor(std::span<const uint8_t> b, uint32_t version, const std::string &ctx) {
  Impostor m = decodeImpostor(b, version, ctx);
  uint64_t used = 0;
  for (const auto &v : m.views)
    used += uint64_t(v.width) * v.height;
  Description d;
  d.add("clip", text(m.clip))
      .add("outfit", text(m.outfit))
      .add("frames", number(m.frames))
      .add("start_time", number(m.startTime))
      .add("frame_step", number(m.frameStep))
      .add("views", text(size2(m.azimuths, m.elevations)))
      .add("texels", number(m.texels))
      .add("sphere_radius", number(m.sphere[3]))
      .add("mirrored", yesNo(m.mirrored))
      .add("atlas", text(size2(m.atlasWidth, m.atlasHeight)))
      .add("occupancy", number(double(used) / (double(m.frames) * m.atlasWidth * m.atlasHeight)))
      .add("bytes_per_frame", number(double(m.bytesPerFrame())))
      .add("uvs", yesNo(!m.uvs.empty()));
  return d;
}

// Per frame: the normals as RGB (n * 0.5 + 0.5, black where empty), the UVs when stored and the
// region ids as distinct greys, decoded as the GPU samples them, so each can be looked at.
std::vector<Image> imagesImpostor(std::span<const uint8_t> b, uint32_t version,
                                  const std::string &ctx) {
  Impostor m = decodeImpostor(b, version, ctx);
  const size_t texels = m.frameTexels();
  const std::string prefix = "impostor_" + m.clip + (m.outfit.empty() ? "" : "_" + m.outfit);
  std::vector<Image> out;
  for (uint32_t f = 0; f < m.frames; ++f) {
    char frame[24];
    std::snprintf(frame, sizeof frame, "_frame_%03u", f);
    const ImpostorTexels t = decodeTexels(m, f);
    Image normals{
        prefix + frame + "_normals", m.atlasWidth, m.atlasHeight, 3, Image::Pixel::U8, {}};
    Image regions{
        prefix + frame + "_regions", m.atlasWidth, m.atlasHeight, 1, Image::Pixel::U8, {}};
    normals.bytes.resize(texels * 3);
    regions.bytes.resize(texels);
    for (size_t i = 0; i < texels; ++i) {
      const auto n = t.normal(i);
      for (size_t k = 0; k < 3; ++k)
        normals.bytes[i * 3 + k] =
            t.regions[i] == 0 ? 0 : uint8_t(std::lround((n[k] * 0.5f + 0.5f) * 255.0f));
      regions.bytes[i] = uint8_t(std::min(255, t.regions[i] * 37));
    }
    out.push_back(std::move(normals));
    if (!t.uv.empty()) {
      Image uv{prefix + frame + "_uv", m.atlasWidth, m.atlasHeight, 3, Image::Pixel::U16, {}};
      uv.bytes.resize(texels * 3 * 2);
      auto *dst = reinterpret_cast<uint16_t *>(uv.bytes.data());
      for (size_t i = 0; i < texels; ++i)
        for (size_t k = 0; k < 3; ++k)
          dst[i * 3 + k] = k < 2 ? uint16_t(std::lround(t.uv[i * 2 + k] * 65535.0f)) : 0;
      out.push_back(std::move(uv));
    }
    out.push_back(std::move(regions));
  }
  return out;
}

} // namespace

namespace {

std::vector<ChunkCodec> &codecTable() {
  static std::vector<ChunkCodec> codecs = {
      {kProvenance, "provenance", 1, kChunkVersion, describeProvenance},
      {kSkeleton, "skeleton", 1, kChunkVersion, describeSkeleton},
      {kClips, "clips", 1, kChunkVersion, describeClips},
      {kAnimationTexture, "animation texture", 1, kChunkVersion, describeAnimation,
       imagesAnimation},
      {kSkinTexture, "skin-weight texture", 1, kChunkVersion, describeSkin, imagesSkin},
      {kMesh, "mesh", 1, kChunkVersion, describeMesh},
      {kDiffuseTexture, "diffuse texture", 1, kChunkVersion, describeTexture, imagesTexture},
      {kLod, "continuous LOD", 1, kChunkVersion, describeLod},
      {kOutfits, "outfits", 1, kChunkVersion, describeOutfits},
      {kSourceMap, "vertex sources", 1, kChunkVersion, describeSourceMap},
      {kMorphs, "morph targets", 1, kChunkVersion, describeMorphs},
      {kLooks, "sub-mesh looks", 1, kChunkVersion, describeLooks},
      {kJointTracks, "joint tracks", 1, kJointTracksVersion, describeJointTracks},
      {kImpostor, "impostor", 1, kImpostorVersion, describeImpostor, imagesImpostor},
      {kCloth, "cloth loop", 1, kClothVersion, describeCloth},
      {kTerrain, "terrain", 1, kTerrainVersion, describeTerrain, imagesTerrain},
  };
  return codecs;
}

} // namespace

const std::vector<ChunkCodec> &chunkCodecs() { return codecTable(); }

void registerChunkCodec(const ChunkCodec &codec) {
  if (findCodec(codec.type))
    throw Error("chunk type " + fourccName(codec.type) + " is registered already");
  if (!codec.describe || codec.oldestVersion == 0 || codec.oldestVersion > codec.version)
    throw Error("chunk type " + fourccName(codec.type) +
                ": a codec needs a describe function "
                "and versions 1 <= oldest <= written");
  codecTable().push_back(codec);
}

std::string formatVersions() {
  std::string s = "crowdpack container " + std::to_string(kContainerVersion);
  s += "; chunks read (written):";
  for (const auto &c : chunkCodecs()) {
    std::string versions = std::to_string(c.oldestVersion);
    if (c.oldestVersion != c.version)
      versions += '-' + std::to_string(c.version);
    s.append("\n  ").append(fourccName(c.type)).append(" ").append(versions);
    s.append(" (").append(std::to_string(c.version)).append(")  ").append(c.title);
  }
  return s;
}

const ChunkCodec *findCodec(uint32_t type) {
  for (const auto &c : chunkCodecs())
    if (c.type == type)
      return &c;
  return nullptr;
}

const ChunkCodec &codecOf(const ChunkEntry &chunk, const std::string &context) {
  const ChunkCodec *codec = findCodec(chunk.type);
  if (!codec) {
    std::string known;
    for (const auto &c : chunkCodecs())
      appendWord(known, fourccName(c.type));
    throw Error(context + ": not a chunk type this build knows (" + known + ")");
  }
  if (chunk.version < codec->oldestVersion || chunk.version > codec->version)
    throw Error(context + ": chunk version " + std::to_string(chunk.version) +
                " is not supported (this build reads " + std::to_string(codec->oldestVersion) +
                ".." + std::to_string(codec->version) + ")");
  return *codec;
}

std::string chunkContext(const Reader &reader, size_t chunkIndex) {
  const auto &chunks = reader.chunks();
  const uint32_t type = chunks[chunkIndex].type;
  std::string ctx = "pack '" + reader.name() + "', chunk " + fourccName(type);
  if (repeatable(type))
    ctx +=
        " #" + std::to_string(std::count_if(chunks.begin(), chunks.begin() + chunkIndex,
                                            [&](const ChunkEntry &c) { return c.type == type; }));
  return ctx;
}

std::string verifyPack(const Reader &reader) {
  for (size_t i = 0; i < reader.chunks().size(); ++i) {
    const std::string ctx = chunkContext(reader, i);
    const ChunkEntry &c = reader.chunks()[i];
    codecOf(c, ctx).describe(reader.payload(c), c.version, ctx);
  }
  std::string line = std::to_string(reader.chunks().size()) + " chunks, " +
                     std::to_string(reader.fileSize()) + " bytes";
  if (!reader.find(kSkeleton) && reader.find(kImpostor)) { // a lone impostor (crowdbake impostor)
    const Impostor m = loadImpostorPack(reader).impostor;
    return line + ", impostor of clip '" + m.clip + "', " + std::to_string(m.frames) + " frames";
  }
  if (!reader.find(kSkeleton) && reader.find(kCloth)) { // a lone loop (crowdbake cloth)
    const ClothLoop m = decodeClothLoop(reader.payload(*reader.find(kCloth)), "pack");
    return line + ", cloth loop of garment '" + m.garment + "' over clip '" + m.clip + "', " +
           std::to_string(m.frameCount()) + " frames";
  }
  if (!reader.find(kSkeleton) && reader.find(kTerrain)) { // an environment (crowdbake terrain)
    const Terrain t = decodeTerrain(reader.payload(*reader.find(kTerrain)), "pack");
    return line + ", terrain of " + size2(t.width, t.depth) + " cells of " + number(t.cell).text;
  }
  const CharacterPack c = loadCharacterPack(reader);
  const AnimationPack &p = c.body;
  line += ", " + std::to_string(p.skeleton.jointCount()) + " joints, " +
          std::to_string(p.clips.size()) + " clips";
  if (p.outfits)
    line += ", " + std::to_string(p.outfits->outfits.size()) + " outfits";
  if (!c.impostors.empty())
    line += ", " + std::to_string(c.impostors.size()) + " impostors";
  if (!c.cloths.empty())
    line += ", " + std::to_string(c.cloths.size()) + " cloth loops";
  return line;
}

} // namespace crowd::pack
