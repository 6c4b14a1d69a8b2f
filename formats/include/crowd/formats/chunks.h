// Chunk schemas of a crowdpack: plain structs, an encoder and a validating decoder for each,
// and a whole-pack load that cross-checks the chunks against each other.
#pragma once
#include <array>
#include <cstdint>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "crowd/formats/container.h"
#include "crowd/formats/joint_tracks.h"

namespace crowd::pack {

inline constexpr uint32_t kProvenance = fourcc("PROV");
inline constexpr uint32_t kSkeleton = fourcc("SKEL");
inline constexpr uint32_t kClips = fourcc("CLIP");
inline constexpr uint32_t kAnimationTexture = fourcc("ANIM");
inline constexpr uint32_t kSkinTexture = fourcc("SKIN");
inline constexpr uint32_t kMesh = fourcc("MESH");
inline constexpr uint32_t kDiffuseTexture = fourcc("TEXR");
inline constexpr uint32_t kLod = fourcc("LODS");
inline constexpr uint32_t kOutfits = fourcc("OUTF");
inline constexpr uint32_t kSourceMap = fourcc("SRCV");
inline constexpr uint32_t kMorphs = fourcc("MRPH");
inline constexpr uint32_t kLooks = fourcc("LOOK");
inline constexpr uint32_t kJointTracks = fourcc("TRAK");
// The version written of every chunk above (formats/src/registry.cpp says which are read).
inline constexpr uint32_t kChunkVersion = 1;

struct InputFile {
  std::string path;  // as given on the command line
  uint64_t size = 0; // bytes
  std::string hash;  // content hash, "algorithm:hex"
};

struct Provenance {
  std::string bakerVersion;
  std::vector<std::pair<std::string, std::string>> settings; // in a fixed order
  std::vector<InputFile> inputs;
};

struct Skeleton {
  std::vector<std::string> names;
  std::vector<int32_t> parents;   // -1 for a root; always < the joint's own index
  std::vector<float> inverseBind; // 16 floats per joint, column-major
  size_t jointCount() const { return names.size(); }
};

struct Clip {
  std::string name;
  float fps = 30;          // frames per second of the stored frames (duration / (frames - 1))
  float startTime = 0;     // seconds: the source time of the clip's frame 0
  uint32_t firstFrame = 0; // frame index within the animation texture
  uint32_t frameCount = 0; // including the closing frame of a looping clip
  bool loop = false;       // the last frame equals the first: playback wraps over frameCount - 1
};

enum class JointEncoding : uint32_t {
  Matrix3x4 = 0, // 3 texels: the rows of the 3x4 joint matrix (global transform x inverse bind)
  QuatTransScale = 1, // 2 texels: rotation quaternion (xyzw); translation xyz + uniform scale
  // QuatTransScale, except the joints of AnimationTexture::matrixJoints, which take 3 texels of
  // matrix rows: the joints whose transforms shear or scale non-uniformly.
  QtsWithMatrices = 2,
};
enum class TexelFormat : uint32_t { RGBA32F = 0, RGBA16F = 1 };

const char *name(JointEncoding e);
const char *name(TexelFormat f);
uint32_t texelsPerJoint(JointEncoding e); // of a joint not listed in matrixJoints
uint32_t bytesPerTexel(TexelFormat f);

// Joint transforms of every frame of every clip. A frame is frameTexels() consecutive texels in
// one row, the joints in order; rows hold framesPerRow frames and never split a frame.
struct AnimationTexture {
  JointEncoding encoding = JointEncoding::Matrix3x4;
  TexelFormat format = TexelFormat::RGBA32F;
  uint32_t width = 0, height = 0;
  uint32_t jointCount = 0;
  uint32_t framesPerRow = 0;
  uint32_t frameCount = 0;
  std::vector<uint32_t> matrixJoints;  // QtsWithMatrices only: ascending, non-empty
  std::vector<uint8_t> texels;         // width * height * bytesPerTexel, row-major
  bool isMatrix(uint32_t joint) const; // stored as 3 matrix rows
  uint32_t frameTexels() const;
  // Texel coordinates of joint `joint`'s first texel in global frame `frame`.
  std::pair<uint32_t, uint32_t> texelOf(uint32_t frame, uint32_t joint) const;
  std::array<float, 4> texel(uint32_t x, uint32_t y) const;
};

// Two RGBA32F texels per vertex: (joint ids as floats), (weights). Vertex v sits at texel 2v.
struct SkinTexture {
  uint32_t width = 0, height = 0;
  uint32_t vertexCount = 0;
  std::vector<float> texels; // width * height * 4
};

struct SubMesh {
  std::string name; // material or region name
  uint32_t firstIndex = 0;
  uint32_t indexCount = 0;
};

struct Mesh {
  std::vector<float> positions; // xyz per vertex, bind pose
  std::vector<float> normals;   // xyz per vertex; (0, 0, 0): flat-shaded, drawn with its face's
  std::vector<float> uvs;       // uv per vertex, or empty
  std::vector<uint32_t> indices;
  std::vector<SubMesh> subMeshes;
  std::array<float, 4> boundingSphere{}; // centre xyz, radius: covers every frame of every clip
  size_t vertexCount() const { return positions.size() / 3; }
};

// The character's diffuse (base colour) texture, RGBA8, rows from the top (glTF UV origin).
struct Texture {
  uint32_t width = 0, height = 0;
  std::vector<uint8_t> rgba;
};

// Continuous LOD of the mesh: its vertices are ordered so that vertex k is the one removed when
// the mesh goes from k + 1 to k vertices, and each sub-mesh's triangles so that, cut at v
// vertices, the sub-mesh is its first triangleCount(s, v) triangles with every index followed
// through `collapse` until it is below v.
struct Lod {
  uint32_t floorVertices = 0;     // the fewest vertices the sequence reaches (>= 1)
  std::vector<uint32_t> collapse; // per vertex: collapse[k] < k from the floor up
  std::vector<float> error;       // per vertex: cost of the collapse that removes it
  // Per sub-mesh, vertexCount + 1 counts (v = 0..vertexCount), non-decreasing in v.
  std::vector<uint32_t> triangleCounts;
  uint32_t triangleCount(size_t subMesh, uint32_t v) const {
    return triangleCounts[subMesh * (collapse.size() + 1) + v];
  }
  // Over every sub-mesh.
  uint64_t totalTriangles(uint32_t v) const {
    uint64_t t = 0;
    for (size_t s = 0; s < triangleCounts.size() / (collapse.size() + 1); ++s)
      t += triangleCount(s, v);
    return t;
  }
};

// How an outfit leaves one sub-mesh of the body template.
enum class Coverage : uint8_t {
  Visible = 0, // drawn whole (no face hidden, or too few to be worth a copy)
  Hidden = 1,  // every face hidden in every frame: not drawn
  Partial = 2, // drawn through an outfit-specific copy holding only its visible faces
};
const char *name(Coverage c);

// The outfits of a clothed character (crowdbake outfits). Sub-meshes [0, bodySubMeshes) are the
// body template; the rest are outfit-specific copies of partial body sub-meshes and garments.
struct Outfits {
  struct Outfit {
    std::string name;
    std::vector<Coverage> coverage;  // per body sub-mesh
    std::vector<uint32_t> subMeshes; // the sub-meshes drawn for this outfit, increasing
  };
  uint32_t bodySubMeshes = 0;
  std::vector<float> colours;    // per sub-mesh: base colour RGBA (the material's)
  std::vector<uint8_t> textured; // per sub-mesh: 1 when the diffuse texture applies
  std::vector<Outfit> outfits;
};

// How each sub-mesh of an unclothed pack looks, from its glTF material: the base colour factor
// and whether the diffuse texture applies (a clothed pack's are in its Outfits). The player starts
// from these, and a scene's palette overrides them.
struct Looks {
  std::vector<float> colours;    // per sub-mesh: base colour RGBA, each in 0..1
  std::vector<uint8_t> textured; // per sub-mesh: 1 when the diffuse texture applies
};

// Where each mesh vertex came from: the glTF file (0: the character's, k: its k-th outfit's),
// node, mesh, primitive and vertex index it was read from. A vertex the bake made is all -1.
struct VertexSource {
  int32_t file = -1, node = -1, mesh = -1, primitive = -1, vertex = -1;
  auto operator<=>(const VertexSource &) const = default;
};
// The source of every mesh vertex, stored compactly: runs of consecutive source vertices of one
// primitive, and per mesh vertex its place in the runs, or nothing when vertex v is the v-th
// (a mesh in import order: a few runs in all).
struct SourceMap {
  struct Run {
    VertexSource first; // first.vertex .. first.vertex + count - 1
    uint32_t count = 0;
  };
  static constexpr uint32_t kMade = UINT32_MAX; // an ordinal: the bake made this vertex
  std::vector<Run> runs;
  std::vector<uint32_t> ordinals; // per mesh vertex: index into the runs' vertices, or kMade

  static SourceMap of(const std::vector<VertexSource> &perVertex);
  uint64_t runVertices() const; // the runs' vertices, all together
  uint64_t vertexCount() const { return ordinals.empty() ? runVertices() : ordinals.size(); }
  std::vector<VertexSource> expand() const; // per mesh vertex
};

// Morph targets: per target, the offsets it adds to the vertices it moves (a range of the mesh),
// and per animation-texture frame up to kMorphSlots active targets with their weights. The
// shader blends a frame's slots with the next frame's, as it blends their joints.
inline constexpr uint32_t kMorphSlots = 8;
struct Morphs {
  struct Target {
    std::string name;
    uint32_t firstVertex = 0, vertexCount = 0; // the range of mesh vertices it moves
    uint64_t firstOffset = 0; // where its range starts in `offsets` (the ranges, one after another)
  };
  struct Slot {
    float target = 0; // a target index (an integer)
    float weight = 0; // 0: the slot is unused
  };
  uint32_t vertexCount = 0; // the mesh's
  std::vector<Target> targets;
  // Per target, per vertex of its range: position offset xyz, 0, normal offset xyz, 0.
  std::vector<float> offsets;
  std::vector<Slot> slots; // kMorphSlots per frame
  uint32_t frameCount() const { return uint32_t(slots.size() / kMorphSlots); }
};

std::vector<uint8_t> encode(const Provenance &);
std::vector<uint8_t> encode(const Skeleton &);
std::vector<uint8_t> encode(const std::vector<Clip> &);
std::vector<uint8_t> encode(const AnimationTexture &);
std::vector<uint8_t> encode(const SkinTexture &);
std::vector<uint8_t> encode(const Mesh &);
std::vector<uint8_t> encode(const Texture &);
std::vector<uint8_t> encode(const Lod &);
std::vector<uint8_t> encode(const Outfits &);
std::vector<uint8_t> encode(const SourceMap &);
std::vector<uint8_t> encode(const Morphs &);
std::vector<uint8_t> encode(const Looks &);

// Decoders validate everything local to the chunk; `context` prefixes error messages.
Provenance decodeProvenance(std::span<const uint8_t>, const std::string &context);
Skeleton decodeSkeleton(std::span<const uint8_t>, const std::string &context);
std::vector<Clip> decodeClips(std::span<const uint8_t>, const std::string &context);
AnimationTexture decodeAnimationTexture(std::span<const uint8_t>, const std::string &context);
SkinTexture decodeSkinTexture(std::span<const uint8_t>, const std::string &context);
Mesh decodeMesh(std::span<const uint8_t>, const std::string &context);
Texture decodeTexture(std::span<const uint8_t>, const std::string &context);
Lod decodeLod(std::span<const uint8_t>, const std::string &context);
Outfits decodeOutfits(std::span<const uint8_t>, const std::string &context);
SourceMap decodeSourceMap(std::span<const uint8_t>, const std::string &context);
Morphs decodeMorphs(std::span<const uint8_t>, const std::string &context);
Looks decodeLooks(std::span<const uint8_t>, const std::string &context);
// Cross-checks an outfit table against the mesh it draws (sub-mesh counts and indices).
void checkOutfits(const Outfits &, const Mesh &, const std::string &context);

// Every chunk of an animation pack, decoded and cross-checked (joint ids < joint count,
// clip frames inside the texture, one skin entry per mesh vertex, ...).
struct AnimationPack {
  Provenance provenance;
  Skeleton skeleton;
  std::vector<Clip> clips;
  // The ANIM chunk. A pack storing joint tracks alone (crowdbake anim --store tracks) has none:
  // then only its joint count and frame count (the clip table's frames) are set, no texels.
  AnimationTexture animation;
  SkinTexture skin;
  Mesh mesh;
  std::optional<Texture> diffuse;   // optional chunk: only when the mesh has UVs and a texture
  std::optional<Lod> lod;           // optional chunk: crowdbake lod, or anim --lod
  std::optional<Outfits> outfits;   // optional chunk: crowdbake outfits
  std::optional<SourceMap> sources; // optional chunk: every bake from glTF writes it
  std::optional<Morphs> morphs;     // optional chunk: when the mesh has morph targets
  std::optional<Looks> looks;       // optional chunk: every bake of an unclothed pack from glTF
  // Optional chunk: compressed joint tracks of the same clips, in the clip table's order
  // (crowdbake anim --store tracks|both); required where the pack has no animation texture.
  std::optional<JointTracks> tracks;
  bool hasTexture() const { return !animation.texels.empty(); }
};
AnimationPack loadAnimationPack(const Reader &reader);
void writePack(const AnimationPack &pack, const std::string &path);
std::vector<uint8_t> packBytes(const AnimationPack &pack);

// IEEE 754 binary16 conversion (round to nearest even), used for RGBA16F texels.
uint16_t floatToHalf(float f);
float halfToFloat(uint16_t h);

} // namespace crowd::pack
