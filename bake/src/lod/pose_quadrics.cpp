#include "pose_quadrics.h"

#include <algorithm>
#include <cmath>
#include <type_traits>

#include "crowd/bake/lod_bake.h"

// The kernels are plain functions over __restrict pointers: with the pointers' ranges unknown,
// GCC gave up on vectorizing loops that read three vertices and write a plane ("no vectype").
// Their branches are arithmetic (a 0 or 1 factor) for the same reason. They are templates over
// the stride: at the default pose count and the bind pose alone it is a constant, the loops
// unroll, and the ten coefficients of a quadric are written in one pass (the sample humanoid's
// LOD bakes 1.08 times faster than with the stride a variable). Each lane's arithmetic is exactly
// the scalar formula's, so the result depends neither on the stride's kind nor on the vector width.
// On x86-64 each kernel is built twice, for the baseline (SSE2: two doubles a vector) and for AVX2
// (four), and the loader picks one by the CPU (GCC's target_clones). No FMA: contracting a * b + c
// would round differently, and the packs must not depend on the machine that baked them. AVX2
// made the 16-pose bake 5-15% faster on the 16 models of tests/bench/lod_speed.sh, byte-identical.
#if defined(__x86_64__) && defined(__GNUC__)
#define CROWD_VECTOR_CLONES [[gnu::target_clones("avx2", "default")]]
#else
#define CROWD_VECTOR_CLONES
#endif
namespace crowd::lod {
namespace {

// Plane rows, each one value per pose: the plane n.x + d = 0 (unit n) and its weight.
enum Row { kX, kY, kZ, kD, kWeight };

// Per pose, the plane of triangle abc, weighted by its area (0, with a unit divisor, where it
// has none: a padding lane).
template <class Stride>
[[gnu::always_inline]] inline void
facePlanes(const double *__restrict a, const double *__restrict b, const double *__restrict c,
           double *__restrict plane, Stride S) {
  for (size_t p = 0; p < S; ++p) {
    const double ux = b[p] - a[p], uy = b[S + p] - a[S + p], uz = b[2 * S + p] - a[2 * S + p];
    const double vx = c[p] - a[p], vy = c[S + p] - a[S + p], vz = c[2 * S + p] - a[2 * S + p];
    const double nx = uy * vz - vy * uz, ny = uz * vx - vz * ux, nz = ux * vy - vx * uy;
    const double area = std::sqrt(nx * nx + ny * ny + nz * nz) * 0.5;
    const double scale = 2 * area + double(area == 0);
    const double x = nx / scale, y = ny / scale, z = nz / scale;
    plane[kX * S + p] = x, plane[kY * S + p] = y, plane[kZ * S + p] = z;
    plane[kD * S + p] = -(x * a[p] + y * a[S + p] + z * a[2 * S + p]);
    plane[kWeight * S + p] = area;
  }
}

// Per pose, the plane through edge ab perpendicular to triangle abc, weighted |ab|^2 (0 where it
// has no direction).
template <class Stride>
[[gnu::always_inline]] inline void
borderPlanes(const double *__restrict a, const double *__restrict b, const double *__restrict c,
             double *__restrict plane, Stride S) {
  for (size_t p = 0; p < S; ++p) {
    const double ux = b[p] - a[p], uy = b[S + p] - a[S + p], uz = b[2 * S + p] - a[2 * S + p];
    const double vx = c[p] - a[p], vy = c[S + p] - a[S + p], vz = c[2 * S + p] - a[2 * S + p];
    const double nx = uy * vz - vy * uz, ny = uz * vx - vz * ux, nz = ux * vy - vx * uy;
    const double ex = uy * nz - ny * uz, ey = uz * nx - nz * ux, ez = ux * ny - nx * uy;
    const double len2 = ex * ex + ey * ey + ez * ez;
    const double some = double(len2 != 0);
    const double inverse = some / std::sqrt(len2 + (1 - some));
    const double x = ex * inverse, y = ey * inverse, z = ez * inverse;
    plane[kX * S + p] = x, plane[kY * S + p] = y, plane[kZ * S + p] = z;
    plane[kD * S + p] = -(x * a[p] + y * a[S + p] + z * a[2 * S + p]);
    plane[kWeight * S + p] = some * (ux * ux + uy * uy + uz * uz);
  }
}

// Per pose, the weighted plane added to quadric q. With a variable stride, coefficient by
// coefficient: ten stores a pose through q were more than GCC would check apart at run time.
template <class Stride>
[[gnu::always_inline]] inline void addPlane(double *__restrict q, const double *__restrict plane,
                                            Stride S) {
  const double *x = plane + kX * S, *y = plane + kY * S, *z = plane + kZ * S, *d = plane + kD * S,
               *w = plane + kWeight * S;
  if constexpr (std::is_same_v<Stride, size_t>) {
    static constexpr Row kFactors[10][2] = {{kX, kX}, {kX, kY}, {kX, kZ}, {kX, kD}, {kY, kY},
                                            {kY, kZ}, {kY, kD}, {kZ, kZ}, {kZ, kD}, {kD, kD}};
    for (size_t k = 0; k < 10; ++k) {
      const double *e = plane + kFactors[k][0] * S, *f = plane + kFactors[k][1] * S;
      double *to = q + k * S;
      for (size_t p = 0; p < S; ++p)
        to[p] += w[p] * e[p] * f[p];
    }
  } else {
    for (size_t p = 0; p < S; ++p) {
      q[p] += w[p] * x[p] * x[p], q[S + p] += w[p] * x[p] * y[p];
      q[2 * S + p] += w[p] * x[p] * z[p], q[3 * S + p] += w[p] * x[p] * d[p];
      q[4 * S + p] += w[p] * y[p] * y[p], q[5 * S + p] += w[p] * y[p] * z[p];
      q[6 * S + p] += w[p] * y[p] * d[p], q[7 * S + p] += w[p] * z[p] * z[p];
      q[8 * S + p] += w[p] * z[p] * d[p], q[9 * S + p] += w[p] * d[p] * d[p];
    }
  }
}

// Per pose, quadric q at position x, plus `plus`.
template <class Stride>
[[gnu::always_inline]] inline void terms(const double *__restrict q, const double *__restrict x,
                                         const double *__restrict plus, double *__restrict out,
                                         Stride S) {
  const double *y = x + S, *z = y + S;
  for (size_t p = 0; p < S; ++p)
    out[p] = x[p] * (q[p] * x[p] + 2 * (q[S + p] * y[p] + q[2 * S + p] * z[p] + q[3 * S + p])) +
             y[p] * (q[4 * S + p] * y[p] + 2 * (q[5 * S + p] * z[p] + q[6 * S + p])) +
             z[p] * (q[7 * S + p] * z[p] + 2 * q[8 * S + p]) + q[9 * S + p] + plus[p];
}

// Per pose, quadric `from` added to quadric q.
template <class Stride>
[[gnu::always_inline]] inline void addQuadric(double *__restrict q, const double *__restrict from,
                                              Stride S) {
  for (size_t i = 0; i < 10 * S; ++i)
    q[i] += from[i];
}

// A stride: a size_t, or a std::integral_constant for a constant one.
template <class Stride> Stride stride(size_t S) {
  if constexpr (std::is_same_v<Stride, size_t>)
    return S;
  else
    return Stride();
}

// The kernels for one kind of stride, each an entry point of its own for the CPU's clone.
template <class Stride> struct KernelsFor {
  CROWD_VECTOR_CLONES static void face(const double *a, const double *b, const double *c,
                                       double *plane, size_t S) {
    facePlanes(a, b, c, plane, stride<Stride>(S));
  }
  CROWD_VECTOR_CLONES static void border(const double *a, const double *b, const double *c,
                                         double *plane, size_t S) {
    borderPlanes(a, b, c, plane, stride<Stride>(S));
  }
  CROWD_VECTOR_CLONES static void add(double *q, const double *plane, size_t S) {
    addPlane(q, plane, stride<Stride>(S));
  }
  CROWD_VECTOR_CLONES static void at(const double *q, const double *x, const double *plus,
                                     double *out, size_t S) {
    terms(q, x, plus, out, stride<Stride>(S));
  }
  CROWD_VECTOR_CLONES static void merge(double *q, const double *from, size_t S) {
    addQuadric(q, from, stride<Stride>(S));
  }
  static PoseQuadrics::Kernels table() { return {&face, &border, &add, &at, &merge}; }
};

// The bind pose plus LodOptions' default pose count, padded to even.
constexpr size_t kDefaultStride = (LodOptions{}.poses + 2) / 2 * 2;

} // namespace

PoseQuadrics::PoseQuadrics(const std::vector<glm::dvec3> &rest,
                           const std::vector<std::vector<glm::vec3>> &poses,
                           const std::vector<uint32_t> &inputOf)
    : poses_(1 + poses.size()), stride_(poses_ == 1 ? 1 : poses_ + poses_ % 2),
      rest_(rest.size() * kRest, 0.0) {
  k_ = stride_ == kDefaultStride
           ? KernelsFor<std::integral_constant<size_t, kDefaultStride>>::table()
       : stride_ == 1 ? KernelsFor<std::integral_constant<size_t, 1>>::table()
                      : KernelsFor<size_t>::table();
  if (poses_ == 1) {
    row_[0] = &rest_[kRestQuadric], row_[1] = &rest_[kRestAt], row_[2] = &rest_[kRestSelf];
    step_[0] = step_[1] = step_[2] = kRest;
  } else {
    q_.assign(rest.size() * 10 * stride_, 0.0);
    at_.assign(rest.size() * 3 * stride_, 0.0);
    self_.assign(rest.size() * stride_, 0.0);
    row_[0] = q_.data(), row_[1] = at_.data(), row_[2] = self_.data();
    step_[0] = 10 * stride_, step_[1] = 3 * stride_, step_[2] = stride_;
  }
  // Each pose's positions looked up once, not through `poses` for every coordinate: that took
  // CesiumMan's constructor (16 poses) about 800,000 cycles, now 320,000-440,000.
  std::vector<const glm::vec3 *> pose(poses.size());
  for (size_t p = 0; p < poses.size(); ++p)
    pose[p] = poses[p].data();
  glm::dvec3 low(0.0), high(0.0);
  for (uint32_t v = 0; v < rest.size(); ++v) {
    low = v == 0 ? rest[v] : glm::min(low, rest[v]);
    high = v == 0 ? rest[v] : glm::max(high, rest[v]);
    for (size_t k = 0; k < 3; ++k)
      rest_[v * kRest + kRestAt + k] = rest[v][int(k)];
    if (poses_ == 1)
      continue;
    double *at = atOf(v);
    for (size_t k = 0; k < 3; ++k)
      at[k * stride_] = rest[v][int(k)];
    for (size_t p = 0; p < pose.size(); ++p) {
      const glm::vec3 &x = pose[p][inputOf[v]];
      at[1 + p] = double(x.x), at[stride_ + 1 + p] = double(x.y);
      at[2 * stride_ + 1 + p] = double(x.z);
    }
  }
  const double diagonal = glm::length(high - low);
  noise_ = kNoise * kNoise * diagonal * diagonal * diagonal * diagonal;
  diagonal2_ = diagonal * diagonal;
}

void PoseQuadrics::addFace(const std::array<uint32_t, 3> &f) {
  const size_t S = stride_;
  k_.facePlanes(atOf(f[0]), atOf(f[1]), atOf(f[2]), plane_.data(), S);
  for (uint32_t v : f)
    k_.addPlane(qOf(v), plane_.data(), S);
}

void PoseQuadrics::addBorder(uint32_t a, uint32_t b, uint32_t c) {
  const size_t S = stride_;
  k_.borderPlanes(atOf(a), atOf(b), atOf(c), plane_.data(), S);
  for (uint32_t v : {a, b})
    k_.addPlane(qOf(v), plane_.data(), S);
}

void PoseQuadrics::finish() {
  for (uint32_t v = 0; v < rest_.size() / kRest; ++v)
    selfAt(v);
}

void PoseQuadrics::selfAt(uint32_t v) {
  k_.terms(qOf(v), atOf(v), zero_.data(), selfOf(v), stride_);
  if (poses_ == 1)
    return; // the rest pose's figures are the only ones
  for (size_t k = 0; k < 10; ++k)
    rest_[v * kRest + kRestQuadric + k] = q_[(v * 10 + k) * stride_];
  rest_[v * kRest + kRestSelf] = self_[v * stride_];
}

void PoseQuadrics::merge(uint32_t into, uint32_t from) {
  k_.addQuadric(qOf(into), qOf(from), stride_);
  selfAt(into);
}

double PoseQuadrics::cost(uint32_t a, uint32_t b) const {
  k_.terms(qOf(a), atOf(b), selfOf(b), term_.data(), stride_);
  double worst = 0;
  for (double t : term_)
    worst = std::max(worst, t);
  return worst < noise_ ? 0.0 : worst;
}

double PoseQuadrics::bound(uint32_t a, uint32_t b) const {
  double rest;
  const double *qa = &rest_[a * kRest + kRestQuadric], *b0 = &rest_[b * kRest];
  terms(qa, b0 + kRestAt, b0 + kRestSelf, &rest, std::integral_constant<size_t, 1>());
  return rest < noise_ ? 0.0 : rest;
}

double PoseQuadrics::key(uint32_t a, uint32_t b, double cost) const {
  if (cost > 0)
    return cost;
  const double *pa = &rest_[a * kRest + kRestAt], *pb = &rest_[b * kRest + kRestAt];
  const double length2 = (pa[0] - pb[0]) * (pa[0] - pb[0]) + (pa[1] - pb[1]) * (pa[1] - pb[1]) +
                         (pa[2] - pb[2]) * (pa[2] - pb[2]);
  int octave = kShortest; // of the length squared over the diagonal's
  if (length2 > 0)
    std::frexp(std::min(length2 / diagonal2_, 1.0), &octave);
  return std::ldexp(0.25 * noise_, std::max(octave, kShortest));
}

} // namespace crowd::lod
