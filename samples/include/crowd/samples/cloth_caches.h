// Sample cloth caches for the cloth-loop bake: the sample dress (outfit_dress.glb, garment
// "dress", every vertex in the glTF's order) simulated over a clip repeated many times, written
// as PC2 at 30 fps. The loose skirts do not repeat exactly within a few cycles; the stiff one
// settles; noise.pc2 never repeats.
#pragma once
#include <string>
#include <vector>

#include <glm/glm.hpp>

namespace crowd::samples {

struct ClothSettings {
  std::string clip;            // the sample clip the body plays, repeated
  uint32_t cycles = 40;        // clip repeats simulated
  double fps = 30.0;           // cache frames per second
  uint32_t substeps = 16;      // solver steps per frame
  float stretchCompliance = 0; // XPBD compliance of edges (m/N); 0 = rigid
  float bendCompliance = 0;    // of the distance across each shared edge
  double damping = 0.0;        // velocity loss per second (fraction)
};

// The files writeClothCaches writes.
inline const std::vector<std::string> kCacheFiles = {"skirt_walk.pc2", "skirt_run.pc2",
                                                     "skirt_stiff.pc2", "noise.pc2"};

struct CacheSample {
  std::string file;
  ClothSettings settings;
};
// skirt_walk.pc2, skirt_run.pc2 (loose, 40 cycles), skirt_stiff.pc2 (stiff, 8 cycles).
const std::vector<CacheSample> &cacheSamples();

// Frames x vertices of the dress, simulated.
std::vector<std::vector<glm::vec3>> simulateDress(const ClothSettings &settings);

// Vertices of the dress garment, as every cache holds them, and its triangles.
uint32_t dressVertexCount();
const std::vector<uint32_t> &dressIndices();

// `frames` x `vertices` positions jittered at random around the dress, every frame anew.
std::vector<std::vector<glm::vec3>> noiseCache(uint32_t frames, uint32_t vertices);

// Writes the cacheSamples() and noise.pc2 (the dress's vertices jittered at random every frame,
// 12 walk cycles) into `dir`.
void writeClothCaches(const std::string &dir);

} // namespace crowd::samples
