#include "crowd/runtime/crowd_renderer.h"

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <cstring>
#include <initializer_list>

#include <epoxy/gl.h>
#include <glm/gtc/type_ptr.hpp>
#include <meshoptimizer.h>

#include "crowd/formats/error.h"
#include "crowd/runtime/environment_renderer.h"
#include "crowd/runtime/impostor_runtime.h"
#include "crowd/runtime/palette_pass.h"
#include "crowd/runtime/region_colour.h"
#include "crowd/runtime/render_queues.h"
#include "crowd/runtime/texture_skinning.h"
#include "crowd_shaders.h" // generated at build time from shaders/
#include "impostor_upload.h"

namespace crowd::runtime {

namespace {

unsigned compile(GLenum type, const char *source, const char *name) {
  unsigned s = glCreateShader(type);
  glShaderSource(s, 1, &source, nullptr);
  glCompileShader(s);
  int ok = 0;
  glGetShaderiv(s, GL_COMPILE_STATUS, &ok);
  if (!ok) {
    char log[4096];
    glGetShaderInfoLog(s, sizeof log, nullptr, log);
    throw Error(std::string("shader ") + name + " does not compile: " + log);
  }
  return s;
}

// Links compiled shaders into a program (and deletes them); throws with the driver's log.
unsigned link(std::initializer_list<unsigned> shaders, const std::string &what) {
  unsigned p = glCreateProgram();
  for (unsigned s : shaders)
    glAttachShader(p, s);
  glLinkProgram(p);
  for (unsigned s : shaders)
    glDeleteShader(s);
  int ok = 0;
  glGetProgramiv(p, GL_LINK_STATUS, &ok);
  if (!ok) {
    char log[4096];
    glGetProgramInfoLog(p, sizeof log, nullptr, log);
    throw Error(what + " do not link: " + log);
  }
  return p;
}

} // namespace

unsigned buildProgram(const char *vertex, const char *fragment, const char *name) {
  return link({compile(GL_VERTEX_SHADER, vertex, (std::string(name) + ".vert").c_str()),
               compile(GL_FRAGMENT_SHADER, fragment, (std::string(name) + ".frag").c_str())},
              std::string("shaders ") + name);
}

unsigned buildComputeProgram(const char *compute, const char *name) {
  return link({compile(GL_COMPUTE_SHADER, compute, (std::string(name) + ".comp").c_str())},
              std::string("shader ") + name);
}

constexpr size_t kInstanceFloats = 20;

namespace {

// A character's GL buffers, by what they hold and where the shaders read them (crowd.vert's
// storage bindings and vertex attributes; impostor.vert's).
struct CharacterBuffers {
  unsigned positions = 0, normals = 0, uvs = 0; // attributes 0, 1, 2
  unsigned lodIndices = 0;   // every LOD level's copy of the indices: the element buffer
  unsigned clips = 0;        // the clip table (clipTable): binding 0
  unsigned instances = 0;    // kInstanceFloats per instance: binding 1
  unsigned colours = 0;      // per palette, per sub-mesh (paletteColours): binding 2
  unsigned morphSlots = 0;   // binding 3
  unsigned morphOffsets = 0; // binding 4
  unsigned clothVertices = 0, clothLoops = 0, clothPositions = 0; // bindings 5, 6, 7
  unsigned jointTexels = 0; // the animation texture's texels as words: binding 8
  unsigned geometryIds = 0; // per queued instance, sorted by level: attribute 3, per instance
  unsigned commands = 0;    // glMultiDrawElementsIndirect's, 5 words each
  // Impostors (impostor.vert): the ids drawn (binding 3), views (4), region ids (5), spans (7).
  unsigned impostorIds = 0, impostorViews = 0, impostorRegions = 0, impostorSpans = 0;
  static constexpr unsigned CharacterBuffers::*kAll[] = {
      &CharacterBuffers::positions,     &CharacterBuffers::normals,
      &CharacterBuffers::uvs,           &CharacterBuffers::lodIndices,
      &CharacterBuffers::clips,         &CharacterBuffers::instances,
      &CharacterBuffers::colours,       &CharacterBuffers::morphSlots,
      &CharacterBuffers::morphOffsets,  &CharacterBuffers::clothVertices,
      &CharacterBuffers::clothLoops,    &CharacterBuffers::clothPositions,
      &CharacterBuffers::jointTexels,   &CharacterBuffers::geometryIds,
      &CharacterBuffers::commands,      &CharacterBuffers::impostorIds,
      &CharacterBuffers::impostorViews, &CharacterBuffers::impostorRegions,
      &CharacterBuffers::impostorSpans};
};

// Its textures: animation (units 0), skin weights (1), diffuse (2); the impostor's normal and
// UV pools (units 0 and 1 of the impostor pass).
struct CharacterTextures {
  unsigned animation = 0, skin = 0, diffuse = 0, impostorNormals = 0, impostorUvs = 0;
  static constexpr unsigned CharacterTextures::*kAll[] = {
      &CharacterTextures::animation, &CharacterTextures::skin, &CharacterTextures::diffuse,
      &CharacterTextures::impostorNormals, &CharacterTextures::impostorUvs};
};

unsigned newTexture(GLenum target) {
  unsigned t = 0;
  glCreateTextures(target, 1, &t);
  return t;
}

} // namespace

struct CrowdRenderer::Character {
  const pack::AnimationPack *pack = nullptr;
  const pack::Impostor *impostor = nullptr;
  unsigned vao = 0;
  CharacterBuffers buffers;
  CharacterTextures textures;
  ClothBuffers cloth;
  // Per instance: 3 rows, params (clip, time offset, speed, palette) and fade (clip faded from
  // or -1, its time offset, fade start, fade length): kInstanceFloats floats.
  std::vector<float> instanceData;
  uint32_t instanceCount = 0;
  std::vector<uint32_t> sceneIndex; // per instance: its index in the scene
  std::vector<uint32_t> clipOf;     // per scene clip: the pack's
  std::vector<uint8_t> clipFits;    // per scene clip: the impostor's clip
  std::vector<uint8_t> outfitFits;  // per instance: the impostor shows its outfit
  ImpostorGpu impostorGpu;
  double diffuseTexelsPerUnit = 0; // of the mesh's surface (runtime::diffuseTexelsPerUnit)
  // Per LOD level, per sub-mesh and one past the last: where its triangles start in
  // buffers.lodIndices.
  std::vector<uint32_t> levelStarts;
  std::vector<uint32_t> commands;        // glMultiDrawElementsIndirect's, 5 words each, by sub-mesh
  std::vector<GLsizei> perSubMesh;       // how many of them each sub-mesh has
  std::vector<uint32_t> outfitOf;        // per instance: its outfit in the pack's table (0 if none)
  RenderQueues queues[2];                // tagged, whole body (render_queues.h)
  std::unique_ptr<PalettePass> palettes; // packs with joint tracks, once drawn from them
  bool skinFromPalettes = false;         // this frame's

  ~Character() {
    glDeleteVertexArrays(1, &vao);
    for (auto b : CharacterBuffers::kAll)
      glDeleteBuffers(1, &(buffers.*b));
    for (auto t : CharacterTextures::kAll)
      glDeleteTextures(1, &(textures.*t));
  }
};

namespace {

// Every texture of a pack must fit this GL implementation (GL_MAX_TEXTURE_SIZE, array layers):
// otherwise GL would fail quietly and draw garbage, so it is one error naming the pack.
void checkTexturesFit(const pack::AnimationPack &p, const pack::Impostor *m,
                      const std::string &pack) {
  GLint side = 0, layers = 0;
  glGetIntegerv(GL_MAX_TEXTURE_SIZE, &side);
  glGetIntegerv(GL_MAX_ARRAY_TEXTURE_LAYERS, &layers);
  auto fit = [&](const char *what, uint64_t w, uint64_t h, uint64_t d = 1) {
    if (w > uint64_t(side) || h > uint64_t(side) || d > uint64_t(layers))
      throw Error("pack '" + pack + "': the " + what + " texture is " + std::to_string(w) + "x" +
                  std::to_string(h) + (d > 1 ? "x" + std::to_string(d) : "") +
                  ", more than this OpenGL allows (" + std::to_string(side) + " texels a side, " +
                  std::to_string(layers) + " layers); bake it smaller");
  };
  if (p.hasTexture())
    fit("animation", p.animation.width, p.animation.height);
  fit("skin weight", p.skin.width, p.skin.height);
  if (p.diffuse)
    fit("diffuse", p.diffuse->width, p.diffuse->height);
  if (m)
    fit("impostor", m->atlasWidth, m->atlasHeight, m->frames);
}

// An instance's world transform, 3 rows of 3x4: rotation `yaw` about +Y, then `position`.
void writeRows(float *d, const glm::vec3 &position, float yaw) {
  const float cy = std::cos(yaw), sy = std::sin(yaw);
  const float rows[12] = {cy, 0, sy, position.x, 0, 1, 0, position.y, -sy, 0, cy, position.z};
  std::copy(rows, rows + 12, d);
}

// A scene's impostor pack drawn with this pack: its clip and outfit must be the pack's.
void checkImpostorMatches(const pack::AnimationPack &p, const pack::Impostor &m,
                          const std::string &name) {
  const bool clip = std::any_of(p.clips.begin(), p.clips.end(),
                                [&](const pack::Clip &k) { return k.name == m.clip; });
  const bool outfit =
      m.outfit.empty() ||
      (p.outfits && std::any_of(p.outfits->outfits.begin(), p.outfits->outfits.end(),
                                [&](const auto &o) { return o.name == m.outfit; }));
  if (!clip || !outfit)
    throw Error("pack '" + name + "': its impostor shows " +
                (clip ? "outfit '" + m.outfit + "', which the pack does not have"
                      : "clip '" + m.clip + "', which the pack does not have") +
                " (bake the impostor from this pack)");
}

// Per scene clip name, its clip in this pack ("" = the first clip).
std::vector<uint32_t> sceneClipsIn(const pack::AnimationPack &p, const Scene &scene, size_t pi) {
  std::vector<uint32_t> clipOf;
  for (const auto &name : scene.clipNames) {
    uint32_t found = name.empty() ? 0 : UINT32_MAX;
    for (uint32_t k = 0; k < p.clips.size() && found == UINT32_MAX; ++k)
      if (p.clips[k].name == name)
        found = k;
    if (found == UINT32_MAX) {
      std::string names;
      for (const auto &cl : p.clips)
        names += (names.empty() ? "" : ", ") + cl.name;
      throw Error(scene.path + ": clip '" + name + "' is not in pack '" + scene.packNames[pi] +
                  "' (clips: " + names + ")");
    }
    clipOf.push_back(found);
  }
  return clipOf;
}

// Per scene outfit name, its outfit in this pack ("" = the first, or none).
std::vector<uint32_t> sceneOutfitsIn(const pack::AnimationPack &p, const Scene &scene, size_t pi) {
  std::vector<uint32_t> outfitOf;
  for (const auto &name : scene.outfitNames) {
    if (name.empty()) {
      outfitOf.push_back(0);
      continue;
    }
    if (!p.outfits)
      throw Error(scene.path + ": outfit '" + name + "' asked of pack '" + scene.packNames[pi] +
                  "', which has no outfits (bake one with crowdbake outfits)");
    const auto &list = p.outfits->outfits;
    auto it = std::find_if(list.begin(), list.end(), [&](auto &o) { return o.name == name; });
    if (it == list.end()) {
      std::string names;
      for (const auto &o : list)
        names += (names.empty() ? "" : ", ") + o.name;
      throw Error(scene.path + ": outfit '" + name + "' is not in pack '" + scene.packNames[pi] +
                  "' (outfits: " + names + ")");
    }
    outfitOf.push_back(uint32_t(it - list.begin()));
  }
  return outfitOf;
}

// The clip table the shader reads: fps, frames, first frame, loop.
std::vector<float> clipTable(const pack::AnimationPack &p) {
  std::vector<float> clips;
  for (const auto &cl : p.clips)
    clips.insert(clips.end(),
                 {cl.fps, float(cl.frameCount), float(cl.firstFrame), cl.loop ? 1.0f : 0.0f});
  return clips;
}

// Per palette, per sub-mesh: RGB, and in A how much the diffuse texture applies.
std::vector<float> paletteColours(const pack::AnimationPack &p, const Scene &scene) {
  std::vector<float> colours;
  for (const auto &palette : scene.palettes)
    for (size_t s = 0; s < p.mesh.subMeshes.size(); ++s) {
      const auto rgba = regionColour(p, s, palette);
      colours.insert(colours.end(), rgba.begin(), rgba.end());
    }

  return colours;
}

} // namespace

// Per pack: its character checked against the scene and placed, then its GPU data.
CrowdRenderer::CrowdRenderer(const std::vector<const pack::AnimationPack *> &packs,
                             const std::vector<const pack::Impostor *> &impostors,
                             const Scene &scene, const std::vector<ClothLoops> &cloths)
    : scene_(scene), schedule_(scene_), light_(scene.lightDirection) {
  program_ = buildProgram(kCrowdVert, kCrowdFrag, "crowd");
  impostorProgram_ = buildProgram(kImpostorVert, kImpostorFrag, "impostor");
  for (size_t pi = 0; pi < packs.size(); ++pi)
    addCharacter(pi, *packs[pi], pi < impostors.size() ? impostors[pi] : nullptr,
                 pi < cloths.size() ? &cloths[pi] : nullptr);
}

void CrowdRenderer::addCharacter(size_t pi, const pack::AnimationPack &p,
                                 const pack::Impostor *impostor, const ClothLoops *cloth) {
  const Scene &scene = scene_;
  characters_.push_back(std::make_unique<Character>());
  Character *c = characters_.back().get();
  c->pack = &p;
  c->impostor = impostor;
  checkTexturesFit(p, c->impostor, scene.packNames[pi]);
  if (c->impostor)
    checkImpostorMatches(p, *c->impostor, scene.packNames[pi]);
  if (cloth) {
    try {
      c->cloth = clothBuffers(p, *cloth);
    } catch (const Error &e) {
      throw Error("pack '" + scene.packNames[pi] + "': " + e.what());
    }
  }
  selection_.addCharacter(p, c->impostor, c->cloth.empty() ? nullptr : &c->cloth.sphere);
  c->clipOf = sceneClipsIn(p, scene, pi);
  for (uint32_t k : c->clipOf)
    c->clipFits.push_back(c->impostor && p.clips[k].name == c->impostor->clip);
  placeInstances(*c, pi, sceneOutfitsIn(p, scene, pi));
  updateClips(*c, characters_.size() - 1, 0.0);
  for (bool wholeBody : {false, true})
    c->queues[wholeBody] =
        RenderQueues(outfitSubMeshes(p, wholeBody), uint32_t(p.mesh.subMeshes.size()));
  uploadGeometry(*c, lodIndexData(*c));
  uploadTextures(*c);
}

// The scene's instances of pack pi: their rows, outfits and whether an impostor may show them.
void CrowdRenderer::placeInstances(Character &c, size_t pi, const std::vector<uint32_t> &outfitOf) {
  const Scene &scene = scene_;
  const pack::AnimationPack &p = *c.pack;
  for (uint32_t i = 0; i < scene.instances.size(); ++i) {
    const Instance &inst = scene.instances[i];
    if (inst.pack != pi)
      continue;
    c.instanceData.resize(c.instanceData.size() + kInstanceFloats);
    writeRows(&c.instanceData[c.instanceData.size() - kInstanceFloats], glm::vec3(inst.position),
              float(inst.yaw));
    c.sceneIndex.push_back(i);
    c.outfitOf.push_back(outfitOf[inst.outfit]);
    // An outfit's impostor shows only that outfit; a bare-body impostor any.
    c.outfitFits.push_back(
        c.impostor &&
        (c.impostor->outfit.empty() ||
         (p.outfits && p.outfits->outfits[outfitOf[inst.outfit]].name == c.impostor->outfit)));
    selection_.addInstance(glm::vec3(inst.position), float(inst.yaw), false);
    ++c.instanceCount;
  }
}

// Index data of every LOD level, built once (see lod_select.h). Each level is a copy of its own,
// so each sub-mesh's triangles there can be in any order: in the order the GPU's vertex cache
// reuses most (meshoptimizer's), not the LOD's (by the collapse that removes them, scattered over
// the mesh), which ran the vertex shader, most of a frame, about twice as often (docs/player.md).
std::vector<uint32_t> CrowdRenderer::lodIndexData(Character &c) {
  const pack::AnimationPack &p = *c.pack;
  std::vector<uint32_t> indices, starts;
  for (uint32_t v : selection_.ladders.back().vertices) {
    auto level = lodIndices(p, v, starts);
    for (size_t s = 0; s + 1 < starts.size(); ++s) {
      const std::vector<uint32_t> lodOrder(level.begin() + starts[s],
                                           level.begin() + starts[s + 1]);
      meshopt_optimizeVertexCache(&level[starts[s]], lodOrder.data(), lodOrder.size(), v);
    }
    for (uint32_t st : starts)
      c.levelStarts.push_back(uint32_t(indices.size()) + st);
    indices.insert(indices.end(), level.begin(), level.end());
  }
  return indices;
}

// The character's buffers and vertex array: mesh, LOD indices, clips, instances, colours, joint
// texels, morphs, cloth (bound even where unread), and the per-frame queues' storage.
void CrowdRenderer::uploadGeometry(Character &c, const std::vector<uint32_t> &indices) {
  const Scene &scene = scene_;
  const pack::AnimationPack &p = *c.pack;
  const std::vector<float> clips = clipTable(p), colours = paletteColours(p, scene);
  glCreateVertexArrays(1, &c.vao);
  for (auto b : CharacterBuffers::kAll)
    glCreateBuffers(1, &(c.buffers.*b));
  auto upload = [](unsigned b, const auto &v) {
    glNamedBufferStorage(b, GLsizeiptr(v.size() * sizeof(v[0])), v.data(), 0);
  };
  upload(c.buffers.positions, p.mesh.positions);
  upload(c.buffers.normals, p.mesh.normals);
  upload(c.buffers.lodIndices, indices);
  upload(c.buffers.clips, clips);
  if (c.instanceData.empty())
    c.instanceData.assign(kInstanceFloats, 0.0f);
  glNamedBufferStorage(c.buffers.instances, GLsizeiptr(c.instanceData.size() * sizeof(float)),
                       c.instanceData.data(),
                       schedule_.dynamic() || scene.world.enabled() ? GL_DYNAMIC_STORAGE_BIT : 0);
  upload(c.buffers.colours, colours);
  upload(c.buffers.jointTexels, p.hasTexture() ? jointTexelWords(p.animation)
                                               : std::vector<int32_t>(2, 0)); // unread, but bound
  upload(c.buffers.morphSlots, morphSlotWords(p.morphs ? &*p.morphs : nullptr));
  upload(c.buffers.morphOffsets, p.morphs ? p.morphs->offsets : std::vector<float>(8, 0.0f));
  if (c.cloth.empty()) { // unread, but bound
    upload(c.buffers.clothVertices, std::vector<int32_t>(2, -1));
    upload(c.buffers.clothLoops, std::vector<GpuClothLoop>(1));
    upload(c.buffers.clothPositions, std::vector<uint32_t>(2, 0));
  } else {
    upload(c.buffers.clothVertices, c.cloth.vertices);
    upload(c.buffers.clothLoops, c.cloth.loops);
    upload(c.buffers.clothPositions, c.cloth.positions);
  }
  // Which instances draw as geometry, and which as impostors: rewritten every frame.
  const size_t queued =
      std::max(c.queues[0].capacity(c.instanceCount), c.queues[1].capacity(c.instanceCount));
  glNamedBufferStorage(c.buffers.geometryIds, GLsizeiptr(std::max<size_t>(queued, 1) * 4), nullptr,
                       GL_DYNAMIC_STORAGE_BIT);
  glNamedBufferStorage(c.buffers.impostorIds, GLsizeiptr(std::max(c.instanceCount, 1u) * 4),
                       nullptr, GL_DYNAMIC_STORAGE_BIT);
  glNamedBufferStorage(c.buffers.commands, GLsizeiptr(c.levelStarts.size() * 5 * sizeof(uint32_t)),
                       nullptr, GL_DYNAMIC_STORAGE_BIT);
  // Attribute 3: the instance's id, one per instance; a command's baseInstance picks its run.
  glVertexArrayVertexBuffer(c.vao, 3, c.buffers.geometryIds, 0, 4);
  glVertexArrayBindingDivisor(c.vao, 3, 1);
  glEnableVertexArrayAttrib(c.vao, 3);
  glVertexArrayAttribIFormat(c.vao, 3, 1, GL_UNSIGNED_INT, 0);
  glVertexArrayAttribBinding(c.vao, 3, 3);
  glVertexArrayVertexBuffer(c.vao, 0, c.buffers.positions, 0, 12);
  glVertexArrayVertexBuffer(c.vao, 1, c.buffers.normals, 0, 12);
  for (unsigned a = 0; a < 2; ++a) {
    glEnableVertexArrayAttrib(c.vao, a);
    glVertexArrayAttribFormat(c.vao, a, 3, GL_FLOAT, GL_FALSE, 0);
    glVertexArrayAttribBinding(c.vao, a, a);
  }
  if (!p.mesh.uvs.empty()) { // otherwise attribute 2 reads its default (0, 0)
    upload(c.buffers.uvs, p.mesh.uvs);
    glVertexArrayVertexBuffer(c.vao, 2, c.buffers.uvs, 0, 8);
    glEnableVertexArrayAttrib(c.vao, 2);
    glVertexArrayAttribFormat(c.vao, 2, 2, GL_FLOAT, GL_FALSE, 0);
    glVertexArrayAttribBinding(c.vao, 2, 2);
  }
  glVertexArrayElementBuffer(c.vao, c.buffers.lodIndices);
}

// Its textures: animation (or a bound placeholder), skin weights, diffuse with mipmaps, impostor.
void CrowdRenderer::uploadTextures(Character &c) {
  const pack::AnimationPack &p = *c.pack;
  auto &t = c.textures;
  t.animation = newTexture(GL_TEXTURE_2D);
  t.skin = newTexture(GL_TEXTURE_2D);
  t.diffuse = newTexture(GL_TEXTURE_2D);
  if (c.impostor) {
    t.impostorNormals = newTexture(GL_TEXTURE_2D_ARRAY);
    t.impostorUvs = newTexture(GL_TEXTURE_2D_ARRAY);
    const unsigned pools[2] = {t.impostorNormals, t.impostorUvs};
    const unsigned buffers[3] = {c.buffers.impostorViews, c.buffers.impostorSpans,
                                 c.buffers.impostorRegions};
    c.impostorGpu = uploadImpostor(*c.impostor, pools, buffers);
  }
  if (p.hasTexture()) {
    const auto &a = p.animation;
    bool half = a.format == pack::TexelFormat::RGBA16F;
    glTextureStorage2D(t.animation, 1, half ? GL_RGBA16F : GL_RGBA32F, GLsizei(a.width),
                       GLsizei(a.height));
    glTextureSubImage2D(t.animation, 0, 0, 0, GLsizei(a.width), GLsizei(a.height), GL_RGBA,
                        half ? GL_HALF_FLOAT : GL_FLOAT, a.texels.data());
  } else { // joint tracks alone: unread (the palettes skin), but bound
    const float zero[4] = {0, 0, 0, 0};
    glTextureStorage2D(c.textures.animation, 1, GL_RGBA32F, 1, 1);
    glTextureSubImage2D(c.textures.animation, 0, 0, 0, 1, 1, GL_RGBA, GL_FLOAT, zero);
  }
  glTextureStorage2D(c.textures.skin, 1, GL_RGBA32F, GLsizei(p.skin.width), GLsizei(p.skin.height));
  glTextureSubImage2D(c.textures.skin, 0, 0, 0, GLsizei(p.skin.width), GLsizei(p.skin.height),
                      GL_RGBA, GL_FLOAT, p.skin.texels.data());
  for (unsigned tex : {c.textures.animation, c.textures.skin}) {
    glTextureParameteri(tex, GL_TEXTURE_MIN_FILTER, GL_NEAREST);
    glTextureParameteri(tex, GL_TEXTURE_MAG_FILTER, GL_NEAREST);
  }
  if (p.diffuse) {
    const auto &d = *p.diffuse;
    c.diffuseTexelsPerUnit = diffuseTexelsPerUnit(p.mesh, d.width, d.height);
    int levels = 1;
    while ((std::max(d.width, d.height) >> levels) > 0)
      ++levels;
    glTextureStorage2D(c.textures.diffuse, levels, GL_RGBA8, GLsizei(d.width), GLsizei(d.height));
    glTextureSubImage2D(c.textures.diffuse, 0, 0, 0, GLsizei(d.width), GLsizei(d.height), GL_RGBA,
                        GL_UNSIGNED_BYTE, d.rgba.data());
    glGenerateTextureMipmap(c.textures.diffuse);
    glTextureParameteri(c.textures.diffuse, GL_TEXTURE_MIN_FILTER, GL_LINEAR_MIPMAP_LINEAR);
    glTextureParameteri(c.textures.diffuse, GL_TEXTURE_MAG_FILTER, GL_LINEAR);
  }
}

CrowdRenderer::~CrowdRenderer() {
  glDeleteProgram(program_);
  glDeleteProgram(impostorProgram_);
  if (paletteProgram_)
    glDeleteProgram(paletteProgram_);
}

void CrowdRenderer::writeClip(Character &c, size_t ci, uint32_t i, const ClipState &s, float speed,
                              double seconds) {
  const float params[8] = {float(c.clipOf[s.clip]),
                           float(s.offset),
                           speed,
                           float(scene_.instances[c.sceneIndex[i]].palette),
                           s.from < 0 ? -1.0f : float(c.clipOf[size_t(s.from)]),
                           float(s.fromOffset),
                           float(s.fadeStart),
                           float(s.fadeSeconds)};
  std::copy(params, params + 8, &c.instanceData[i * kInstanceFloats + 12]);
  // Mid-fade, an instance draws as geometry: the impostor shows one clip.
  selection_.characters[ci].eligible[i] =
      c.clipFits[s.clip] && c.outfitFits[i] && s.weightAt(seconds) >= 1.0f;
}

void CrowdRenderer::updateClips(Character &c, size_t ci, double seconds) {
  for (uint32_t i = 0; i < c.instanceCount; ++i)
    writeClip(c, ci, i, schedule_.at(c.sceneIndex[i], seconds),
              float(scene_.instances[c.sceneIndex[i]].speed), seconds);
}

uint64_t CrowdRenderer::impostorBytes() const {
  uint64_t bytes = 0;
  for (const auto &c : characters_)
    bytes += c->impostorGpu.bytes;
  return bytes;
}

void CrowdRenderer::attachWorld(SceneWorld &world) {
  if (!scene_.world.enabled())
    throw Error(scene_.path + ": a world needs the scene's \"world\"");
  world_ = &world;
  environment_ = std::make_unique<EnvironmentRenderer>(world.terrain());
  // The terrain's shadows were baked for its light: the scene is lit by the same.
  const auto &l = world.terrain().light;
  light_ = glm::normalize(glm::vec3(l[0], l[1], l[2]));
}

void CrowdRenderer::setShadowPass(bool on) {
  if (!world_)
    return;
  const glm::vec4 shadow(light_, on ? 1.0f : 0.0f);
  for (unsigned program : {program_, impostorProgram_})
    glProgramUniform4fv(program, glGetUniformLocation(program, "u_shadow"), 1,
                        glm::value_ptr(shadow));
  if (on) { // darken (multiply) each pixel once, never write depth
    glEnable(GL_STENCIL_TEST);
    glStencilFunc(GL_EQUAL, 0, 0xFF);
    glStencilOp(GL_KEEP, GL_KEEP, GL_INCR);
    glEnable(GL_BLEND);
    glBlendFunc(GL_ZERO, GL_SRC_COLOR);
    glDepthMask(GL_FALSE);
  } else {
    glDisable(GL_STENCIL_TEST);
    glDisable(GL_BLEND);
    glDepthMask(GL_TRUE);
  }
}

void CrowdRenderer::moveInstances(Character &c, size_t ci, double seconds) {
  for (uint32_t i = 0; i < c.instanceCount; ++i) {
    const InstanceMotion &m = world_->motions()[c.sceneIndex[i]];
    writeRows(&c.instanceData[i * kInstanceFloats], m.position, m.yaw);
    selection_.moveInstance(ci, i, m.position, m.yaw);
    writeClip(c, ci, i, m.clip, m.speed, seconds);
  }
}

// The geometry pass's state for character c: its uniforms, vertex array, textures and
// storage buffers (crowd.vert's bindings), and its palettes where it skins from them.
void CrowdRenderer::bindGeometry(const Character &c) {
  auto loc = [&](const char *name) { return glGetUniformLocation(program_, name); };
  const auto &p = *c.pack;
  const size_t subMeshes = p.mesh.subMeshes.size();
  glUseProgram(program_);
  glUniform1i(loc("u_frameTexels"), int(p.animation.frameTexels()));
  glUniform1i(loc("u_framesPerRow"), int(p.animation.framesPerRow));
  glUniform1i(loc("u_skinWidth"), int(p.skin.width));
  glUniform1i(loc("u_subMeshCount"), int(subMeshes));
  glBindVertexArray(c.vao);
  glBindTextureUnit(0, c.textures.animation);
  glBindTextureUnit(1, c.textures.skin);
  glBindTextureUnit(2, c.textures.diffuse);
  glUniform1i(loc("u_hasTexture"), p.diffuse ? 1 : 0);
  glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 0, c.buffers.clips);
  glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 1, c.buffers.instances);
  glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 2, c.buffers.colours);
  glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 3, c.buffers.morphSlots);
  glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 4, c.buffers.morphOffsets);
  glUniform1i(loc("u_morphs"), p.morphs ? 1 : 0);
  glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 5, c.buffers.clothVertices);
  glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 6, c.buffers.clothLoops);
  glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 7, c.buffers.clothPositions);
  glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 8, c.buffers.jointTexels);
  glUniform1i(loc("u_cloth"), c.cloth.empty() ? 0 : 1);
  glUniform1i(loc("u_clothClips"), int(c.cloth.clips));
  glUniform1i(loc("u_rootJoint"), int(c.cloth.rootJoint));
  glUniformMatrix4fv(loc("u_rootBind"), 1, GL_FALSE, glm::value_ptr(c.cloth.rootBind));
  glUniform1i(loc("u_palettes"), c.skinFromPalettes ? 1 : 0);
  if (c.skinFromPalettes) {
    glUniform1i(loc("u_joints"), int(c.palettes->joints()));
    c.palettes->bind();
  }
}

// Character c's geometry instances: by sub-mesh through the queues' indirect commands, or on
// the naive path one draw per instance and sub-mesh at full detail.
void CrowdRenderer::drawGeometry(const Character &c, const CrowdSelection::Character &chosen,
                                 const RenderQueues &queues, bool naive, DrawStats &stats) {
  auto loc = [&](const char *name) { return glGetUniformLocation(program_, name); };
  const int subMeshLoc = loc("u_subMesh"), rowsLoc = loc("u_rows"), paramsLoc = loc("u_params");
  static_assert(kInstanceFloats == 20); // u_params[2]: an instance's params and fade
  const size_t subMeshes = c.pack->mesh.subMeshes.size(), levels = chosen.runEnds.size();
  glBindBuffer(GL_DRAW_INDIRECT_BUFFER, c.buffers.commands);
  size_t command = 0;
  for (size_t s = 0; s < subMeshes; ++s) {
    glUniform1i(subMeshLoc, int(s));
    if (naive) { // full detail: the last level
      const uint32_t *starts = &c.levelStarts[(levels - 1) * (subMeshes + 1)];
      const void *offset = reinterpret_cast<const void *>(uintptr_t(starts[s]) * 4);
      const auto count = GLsizei(starts[s + 1] - starts[s]);
      for (uint32_t i = 0; i < c.instanceCount; ++i) {
        const auto &draws = queues.draws(c.outfitOf[i]);
        if (!std::binary_search(draws.begin(), draws.end(), uint32_t(s)))
          continue;
        glUniform4fv(rowsLoc, 3, &c.instanceData[i * kInstanceFloats]);
        glUniform4fv(paramsLoc, 2, &c.instanceData[i * kInstanceFloats + 12]);
        if (c.skinFromPalettes)
          glUniform1i(loc("u_palette"), c.palettes->paletteOf(i));
        glDrawElements(GL_TRIANGLES, count, GL_UNSIGNED_INT, offset);
        ++stats.drawCalls;
        stats.triangles += uint64_t(count / 3);
      }
      continue;
    }
    if (c.perSubMesh[s]) {
      glMultiDrawElementsIndirect(GL_TRIANGLES, GL_UNSIGNED_INT,
                                  reinterpret_cast<const void *>(command * 20), c.perSubMesh[s], 0);
      ++stats.drawCalls;
    }
    command += size_t(c.perSubMesh[s]);
  }
}

// Character c's impostors, one instanced strip: the impostor program's uniforms and bindings.
void CrowdRenderer::drawImpostors(const Character &c, const CrowdSelection::Character &chosen,
                                  const FrameView &view, float seconds, bool shadow,
                                  DrawStats &stats) {
  const auto &p = *c.pack;
  const pack::Impostor &m = *c.impostor;
  glUseProgram(impostorProgram_);
  auto iloc = [&](const char *name) { return glGetUniformLocation(impostorProgram_, name); };
  glUniformMatrix4fv(iloc("u_viewProjection"), 1, GL_FALSE, glm::value_ptr(view.viewProjection));
  glUniform1f(iloc("u_time"), seconds);
  glUniform3fv(iloc("u_eye"), 1, glm::value_ptr(view.eye));
  glUniform4fv(iloc("u_sphere"), 1, m.sphere.data());
  glUniform4i(iloc("u_layout"), int(m.azimuths), int(m.elevations), int(m.storedAzimuths()),
              int(m.frames));
  glUniform1i(iloc("u_mirrored"), m.mirrored);
  glUniform1f(iloc("u_frameStep"), m.frameStep > 0 ? m.frameStep : 1.0f);
  glUniform1f(iloc("u_texelSize"), 2.0f * m.sphere[3] / float(m.texels));
  glUniform1f(iloc("u_diffusePerTexel"),
              float(c.diffuseTexelsPerUnit * 2.0 * m.sphere[3] / double(m.texels)));
  glUniform1f(iloc("u_oneToOne"), float(oneToOneDistance(m, view.fovY, view.viewportHeight)));
  const ImpostorGpu &g = c.impostorGpu;
  glUniform1i(iloc("u_maxLevel"), int(g.levels) - 1);
  glUniform1i(iloc("u_regionBits"), int(g.regionBits));
  glUniform1i(iloc("u_regionFrameWords"), int(g.regionFrameWords));
  glUniform1iv(iloc("u_regionLevelWord"), kImpostorMaxMipLevels, g.regionLevelWord.data());
  glUniform1iv(iloc("u_regionRowWords"), kImpostorMaxMipLevels, g.regionRowWords.data());
  glUniform1i(iloc("u_poolShift"), int(g.poolShift));
  glUniform1i(iloc("u_viewCount"), int(m.views.size()));
  glUniform1i(iloc("u_hasTexture"), p.diffuse ? 1 : 0);
  glUniform1i(iloc("u_hasUvs"), !m.uvs.empty());
  glUniform1i(iloc("u_subMeshCount"), int(p.mesh.subMeshes.size()));
  glUniform3fv(iloc("u_lightDirection"), 1, glm::value_ptr(light_));
  glBindTextureUnit(0, c.textures.impostorNormals);
  glBindTextureUnit(1, c.textures.impostorUvs);
  glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 3, c.buffers.impostorIds);
  glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 4, c.buffers.impostorViews);
  glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 5, c.buffers.impostorRegions);
  glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 7, c.buffers.impostorSpans);
  glDrawArraysInstanced(GL_TRIANGLE_STRIP, 0, 4, GLsizei(chosen.impostorIds.size()));
  ++stats.drawCalls;
  if (!shadow)
    stats.triangles += 2 * uint64_t(chosen.impostorIds.size());
}

void CrowdRenderer::drawCharacter(const Character &c, const CrowdSelection::Character &chosen,
                                  const RenderQueues &queues, const FrameView &view, float seconds,
                                  bool naive, bool shadow, DrawStats &stats) {
  bindGeometry(c);
  drawGeometry(c, chosen, queues, naive, stats);
  if (!chosen.impostorIds.empty())
    drawImpostors(c, chosen, view, seconds, shadow, stats);
}

// A frame's start at `seconds`: the world's agents move the instances and the environment is
// drawn (its grid and shadows bound for the characters), or the schedule's clips are written.
// Returns the time the clips took, in ms (the agents' is stats.agentsMs).
double CrowdRenderer::beginFrame(const FrameView &view, double seconds, DrawStats &stats) {
  double clipsMs = 0;
  if (world_) { // the agents move the instances; the environment is drawn first
    const auto t0 = std::chrono::steady_clock::now();
    world_->advanceTo(seconds);
    for (size_t ci = 0; ci < characters_.size(); ++ci) {
      Character &c = *characters_[ci];
      moveInstances(c, ci, seconds);
      glNamedBufferSubData(c.buffers.instances, 0,
                           GLsizeiptr(c.instanceData.size() * sizeof(float)),
                           c.instanceData.data());
    }
    stats.agentsMs =
        std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
    environment_->draw(view.viewProjection, light_);
    glClear(GL_STENCIL_BUFFER_BIT); // the shadow pass's: each pixel darkened once
    const glm::vec4 grid = environment_->grid();
    for (unsigned program : {program_, impostorProgram_})
      glProgramUniform4fv(program, glGetUniformLocation(program, "u_grid"), 1,
                          glm::value_ptr(grid));
    glBindTextureUnit(5, environment_->shadowHeights());
  } else if (schedule_.dynamic())
    for (size_t ci = 0; ci < characters_.size(); ++ci) {
      Character &c = *characters_[ci];
      const auto t0 = std::chrono::steady_clock::now();
      updateClips(c, ci, seconds);
      clipsMs +=
          std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
      glNamedBufferSubData(c.buffers.instances, 0,
                           GLsizeiptr(c.instanceData.size() * sizeof(float)),
                           c.instanceData.data());
    }
  return clipsMs;
}

// Character c's queues for this frame (the instances chosen as geometry, by sub-mesh and
// level), its indirect commands and impostor ids uploaded.
RenderQueues &CrowdRenderer::queueCharacter(Character &c, const CrowdSelection::Character &chosen,
                                            bool wholeBody, DrawStats &stats) {
  const size_t subMeshes = c.pack->mesh.subMeshes.size();
  RenderQueues &queues = c.queues[wholeBody];
  const auto t0 = std::chrono::steady_clock::now();
  queues.build(chosen.ids, chosen.runEnds, c.outfitOf);
  stats.cullSelectMs +=
      std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
  c.commands.clear();
  c.perSubMesh.assign(subMeshes, 0);
  for (const auto &q : queues.queues) { // by sub-mesh, then level
    const uint32_t *starts = &c.levelStarts[q.level * (subMeshes + 1)];
    const uint32_t indices = starts[q.subMesh + 1] - starts[q.subMesh];
    if (indices) {
      c.commands.insert(c.commands.end(), {indices, q.count, starts[q.subMesh], 0u, q.first});
      ++c.perSubMesh[q.subMesh];
      stats.triangles += uint64_t(indices / 3) * q.count;
    }
  }
  glNamedBufferSubData(c.buffers.geometryIds, 0, GLsizeiptr(queues.queueIds.size() * 4),
                       queues.queueIds.data());
  glNamedBufferSubData(c.buffers.impostorIds, 0, GLsizeiptr(chosen.impostorIds.size() * 4),
                       chosen.impostorIds.data());
  glNamedBufferSubData(c.buffers.commands, 0, GLsizeiptr(c.commands.size() * 4), c.commands.data());
  return queues;
}

// Skinning palettes for the instances drawn as geometry (all of them on the naive path) where
// character ci skins from joint tracks this frame: a pack of tracks alone always does.
void CrowdRenderer::runPalettes(Character &c, size_t ci, const CrowdSelection::Character &chosen,
                                float seconds, const DrawOptions &options, DrawStats &stats) {
  const auto &p = *c.pack;
  const bool naive = options.path == DrawPath::Naive;
  c.skinFromPalettes = p.tracks && (options.trackSkinning || !p.hasTexture());
  if (c.skinFromPalettes && !c.palettes) { // built on first use: most frames draw textures
    if (!paletteProgram_)
      paletteProgram_ = buildComputeProgram(kPaletteComp, "palette");
    try {
      c.palettes = std::make_unique<PalettePass>(p, c.instanceCount, scene_.paletteSlot);
    } catch (const Error &e) {
      throw Error("pack '" + scene_.packNames[ci] + "': " + e.what());
    }
  }
  if (c.skinFromPalettes) {
    const auto t1 = std::chrono::steady_clock::now();
    std::vector<uint32_t> all;
    if (naive)
      for (uint32_t i = 0; i < c.instanceCount; ++i)
        all.push_back(i);
    stats.palettes += c.palettes->run(paletteProgram_, c.instanceData, kInstanceFloats,
                                      naive ? all : chosen.ids, seconds, options.timePalettes);
    stats.paletteGpuMs += c.palettes->gpuMilliseconds();
    stats.paletteMs +=
        std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t1).count();
    glUseProgram(program_);
  }
}

DrawStats CrowdRenderer::draw(const FrameView &view, float seconds, const DrawOptions &options) {
  DrawStats stats;
  const bool naive = options.path == DrawPath::Naive;
  const double clipsMs = beginFrame(view, seconds, stats);
  const auto chosen = selection_.select(view, options);
  stats.visible = chosen.visible;
  stats.impostors = chosen.impostors;
  stats.cullSelectMs = chosen.milliseconds + clipsMs;

  glUseProgram(program_);
  auto loc = [&](const char *name) { return glGetUniformLocation(program_, name); };
  glUniformMatrix4fv(loc("u_viewProjection"), 1, GL_FALSE, glm::value_ptr(view.viewProjection));
  glUniform1f(loc("u_time"), seconds);
  glUniform3fv(loc("u_lightDirection"), 1, glm::value_ptr(light_));
  glUniform1i(loc("u_naive"), naive);
  for (size_t ci = 0; ci < characters_.size(); ++ci) {
    Character &c = *characters_[ci];
    const auto &picked = selection_.characters[ci];
    stats.instances += c.instanceCount;
    if (c.instanceCount == 0)
      continue;
    const RenderQueues &queues = queueCharacter(c, picked, options.wholeBody, stats);
    runPalettes(c, ci, picked, seconds, options, stats);
    // With a world, a shadow pass first (Tecchia, Loscos & Chrysanthou §4.5): every character flat
    // on its ground along the light, each pixel darkened once (stencil), behind what is nearer
    // (depth).
    for (int pass = world_ && !naive ? 0 : 1; pass < 2; ++pass) {
      setShadowPass(pass == 0);
      drawCharacter(c, picked, queues, view, seconds, naive, pass == 0, stats);
    }
  }
  setShadowPass(false);
  return stats;
}

} // namespace crowd::runtime
