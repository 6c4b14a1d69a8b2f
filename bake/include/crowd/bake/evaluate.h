// Exact evaluation of a Character's glTF animation at any time (no resampling) and the
// reference CPU skinning every accuracy figure is measured against. All in double precision.
#pragma once
#include <cstdint>
#include <vector>

#include "crowd/bake/character.h"

namespace crowd {

// A channel's value at time t, as glTF interpolates it: `out` gets ch.components values
// (rotations normalized). At a key time the key's value; `fromLeft`: the limit from before t,
// which differs only at a cut (two keys at one time: the first) and under STEP (the key before).
void sampleChannel(const Channel &ch, double t, double *out, bool fromLeft = false);
// Every node's local translation, rotation and scale (a node with a matrix keeps its matrix).
struct NodeLocals {
  std::vector<glm::dvec3> translation;
  std::vector<glm::dquat> rotation;
  std::vector<glm::dvec3> scale;
};
// At time t of `clip` (null: the rest pose).
NodeLocals nodeLocals(const Character &c, const AnimationClip *clip, double t);
// `weight` of the way from `from` to `to`: rotations slerped the shorter way, the rest lerped,
// as the player crossfades joint tracks.
NodeLocals blendLocals(const NodeLocals &from, const NodeLocals &to, double weight);
// Global transform of every node at time t of `clip` (null: the rest pose), or of given locals.
std::vector<glm::dmat4> nodeGlobals(const Character &c, const AnimationClip *clip, double t);
std::vector<glm::dmat4> nodeGlobals(const Character &c, const NodeLocals &locals);
// Joint matrices (global joint transform x inverse bind) at time t, or of given locals.
std::vector<glm::dmat4> jointMatrices(const Character &c, const AnimationClip *clip, double t);
std::vector<glm::dmat4> jointMatrices(const Character &c, const NodeLocals &locals);
// Morph target weights at time t of `clip` (null: the rest pose): the mesh's defaults where no
// channel drives a target.
std::vector<double> morphWeights(const Character &c, const AnimationClip *clip, double t);
// Vertex v's bind-pose position morphed by the given weights.
glm::dvec3 morphedPosition(const SkinnedMesh &m, const std::vector<double> &morphWeights, size_t v);
// Vertex v's position for the given joint matrices and morph weights: morphed, then skinned.
glm::dvec3 skinPosition(const SkinnedMesh &m, const std::vector<glm::dmat4> &joints,
                        const std::vector<double> &morphWeights, size_t v);
// Every vertex's (skinPosition).
std::vector<glm::dvec3> skinPositions(const Character &c, const std::vector<glm::dmat4> &joints,
                                      const std::vector<double> &morphWeights);
// The vertices at time t of `clip` (null: the rest pose), exactly: the reference every accuracy
// figure is measured against.
std::vector<glm::dvec3> posedPositions(const Character &c, const AnimationClip *clip, double t);

// Per triangle, the sign that turns its winding as drawn (cross(b - a, c - a) of its posed
// corners) to its outward side: the side its vertex normals point to. Normals are stored in the
// mesh's own frame, where a face under a mirroring node (stored wound as drawn: the importer turns
// it round) disagrees with them; the rest pose's skinning says which vertices it mirrors.
std::vector<double> outwardSides(const Character &c);
// Size of the bounding box of the rest-pose skinned mesh along x, y (glTF's up) and z.
glm::dvec3 restExtent(const Character &c);
// Its diagonal: the unit of relative errors.
double restDiagonal(const Character &c);

} // namespace crowd
