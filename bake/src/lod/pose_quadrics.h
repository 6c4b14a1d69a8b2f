// The LOD's error quadrics, one per vertex per pose. A collapse of a into b costs (Qa + Qb) at
// b's position in the pose where that is largest: the worst frame is what the player shows. The
// rest pose counts as one pose among them, weighted as the others (docs/bakes/lod.md says why).
#pragma once
#include <array>
#include <cstddef>
#include <cstdint>
#include <vector>

#include <glm/glm.hpp>

namespace crowd::lod {

// Every vertex's quadric (symmetric 4x4: xx xy xz xw yy yz yw zz zw ww) in every pose, pose-
// minor: coefficient k of vertex v in pose p at (v * 10 + k) * stride + p, the poses padded with
// zeros to an even count (the rest pose alone: stride 1, in rest_). Every loop runs over the
// poses, one a lane, so that the compiler evaluates two or more poses at once; each pose's
// arithmetic is the same as one at a time.
class PoseQuadrics {
public:
  // Vertex v at rest[v] in the rest pose, the first, and at poses[p][inputOf[v]] in pose p + 1.
  PoseQuadrics(const std::vector<glm::dvec3> &rest,
               const std::vector<std::vector<glm::vec3>> &poses,
               const std::vector<uint32_t> &inputOf);
  PoseQuadrics(const PoseQuadrics &) = delete; // row_ points into its own arrays
  PoseQuadrics &operator=(const PoseQuadrics &) = delete;
  // Adds the face's plane, weighted by its area, to its corners' quadrics in every pose where it
  // has an area.
  void addFace(const std::array<uint32_t, 3> &f);
  // Adds, to the ends of the open or seam edge ab of face abc in every pose, a plane through the
  // edge perpendicular to the face, weighted the edge's squared length (as a face of about that
  // area would be): straightening the line or cutting across it costs what moving the surface
  // as far would (a heavier weight held borders so hard that the rest of the mesh paid).
  void addBorder(uint32_t a, uint32_t b, uint32_t c);
  void finish(); // after the last plane
  // b takes on a's quadric as a collapses into it.
  void merge(uint32_t into, uint32_t from);
  // The most surface moved, over the poses, when a goes to b; 0 below the noise floor: moving a
  // face as large as the rest pose's diagonal by kNoise of it. Costs that small are rounding, not
  // shape: posed by float skinning, the flat faces of a rigid part cost 1e-18 instead of 0, and
  // the skinning-aware order of the robot's boxes (every pose the same shape) was rounding's.
  double cost(uint32_t a, uint32_t b) const;
  // cost(a, b)'s lower bound from the rest pose alone (the first pose), about 1/16 of its work at
  // the default 16 poses; the cost itself where the rest pose is the only one.
  double bound(uint32_t a, uint32_t b) const;
  bool boundIsCost() const { return poses_ == 1; }
  // Where a collapse of this cost (cost() or bound()) queues: at the cost itself, or where that is
  // 0, below every cost above the noise floor, by the octave of its edge's length in the rest
  // pose, shorter first: in one bucket, a flat region's free collapses all went into one vertex
  // whose ring grew with each. Within an octave they stay last pushed first, near each other
  // (ordered by exact length they swept the mesh, and ran slower).
  double key(uint32_t a, uint32_t b, double cost) const;
  static constexpr int kShortest = -200; // the octave of edges that short or shorter
  static constexpr double kNoise = 1e-6;

  // The loops over the poses, for this stride (pose_quadrics.cpp).
  struct Kernels {
    void (*facePlanes)(const double *, const double *, const double *, double *, size_t);
    void (*borderPlanes)(const double *, const double *, const double *, double *, size_t);
    void (*addPlane)(double *, const double *, size_t);
    void (*terms)(const double *, const double *, const double *, double *, size_t);
    void (*addQuadric)(double *, const double *, size_t);
  };

private:
  void selfAt(uint32_t v);
  // Vertex v's quadric, position and self term, stride_ values a row: in the pose-minor arrays,
  // or where the rest pose is the only one (stride 1) in rest_, which then holds everything.
  double *qOf(uint32_t v) const { return row_[0] + size_t(v) * step_[0]; }
  double *atOf(uint32_t v) const { return row_[1] + size_t(v) * step_[1]; }
  double *selfOf(uint32_t v) const { return row_[2] + size_t(v) * step_[2]; }
  size_t poses_, stride_;
  double noise_, diagonal2_;
  Kernels k_;
  // Quadrics, positions (x y z) and each quadric at its own vertex (Qb at b, which changes only
  // when b does), all pose-minor; empty where the rest pose is the only one.
  std::vector<double> q_, at_, self_;
  // The rest pose's (the first pose's) quadric, position and self term of each vertex side by
  // side, for bound(): spread over the pose-minor rows, they cost a cache miss each. With no
  // other pose, the only copy: a second, padded to two lanes, made a 1M-triangle grid's bake
  // hold 112 MB more and add every merge twice.
  // A vertex's record in rest_: its quadric's ten coefficients, its position, its self term.
  enum RestField : size_t { kRestQuadric = 0, kRestAt = 10, kRestSelf = 13, kRest = 14 };
  std::vector<double> rest_;
  double *row_[3]; // qOf, atOf, selfOf's first vertex, and the step from one to the next
  size_t step_[3];
  std::vector<double> plane_ = std::vector<double>(5 * stride_); // x y z d weight
  std::vector<double> zero_ = std::vector<double>(stride_);
  mutable std::vector<double> term_ = std::vector<double>(stride_);
};

} // namespace crowd::lod
