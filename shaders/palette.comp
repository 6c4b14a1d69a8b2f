#version 450 core
// The palette pass: one invocation per palette request decodes compressed joint tracks at a clip
// time (in a crossfade, at both clips' times, their local poses blended), composes them local to
// global along the hierarchy and writes each joint's matrix (global x inverse bind) as 3 rows.
// runtime/src/track_palettes.cpp and track_pose.cpp are its CPU mirror; TrackWords the layout.
layout(local_size_x = 32) in;

// Per palette: (clip, seconds, clip faded from or -1, its seconds), (weight of the first, 0, 0, 0).
layout(std430, binding = 0) readonly buffer Requests { vec4 requests[]; };
layout(std430, binding = 1) readonly buffer Rig { uint rig[]; };       // nodes, then joints
layout(std430, binding = 2) readonly buffer Tracks { uint tracks[]; }; // clips, then tracks
layout(std430, binding = 3) readonly buffer Times { float times[]; };
layout(std430, binding = 4) readonly buffer Stream { uint stream[]; };
layout(std430, binding = 5) writeonly buffer Palettes { vec4 palettes[]; }; // 3 per joint
layout(std430, binding = 6) buffer Globals { mat4 globals[]; };             // per node

uniform int u_requests, u_nodes, u_joints, u_clips;

const uint kNodeWords = 16u, kJointWords = 20u, kClipWords = 4u, kTrackWords = 8u;

float word(uint w) { return uintBitsToFloat(w); }

uint readBits(uint base, uint at, uint bits) {
  uint index = base + at / 32u, shift = at % 32u;
  uint v = stream[index] >> shift;
  if (shift + bits > 32u)
    v |= stream[index + 1u] << (32u - shift);
  return v & ((1u << bits) - 1u);
}

struct Span {
  uint first, second;
  float alpha;
};

// The samples around `seconds` in clip `clip` (sampleSpan): the first time after it, found by
// bisection.
Span spanOf(uint clip, float seconds) {
  uint first = tracks[clip * kClipWords], n = tracks[clip * kClipWords + 1u];
  uint lo = 0u, hi = n;
  while (lo < hi) {
    uint mid = (lo + hi) / 2u;
    if (times[first + mid] <= seconds)
      lo = mid + 1u;
    else
      hi = mid;
  }
  if (lo == 0u)
    return Span(0u, 0u, 0.0);
  if (lo == n)
    return Span(n - 1u, n - 1u, 0.0);
  float t0 = times[first + lo - 1u], t1 = times[first + lo];
  return Span(lo - 1u, lo, (seconds - t0) / (t1 - t0));
}

vec3 trackSample(uint track, uint base, uint index) {
  uint t = uint(u_clips) * kClipWords + track * kTrackWords;
  uint bits = (tracks[t] >> 16) & 0xffu;
  float top = float((1u << bits) - 1u);
  uint at = tracks[t + 1u] + index * 3u * bits;
  vec3 v;
  for (uint c = 0u; c < 3u; ++c, at += bits)
    v[c] = word(tracks[t + 2u + c]) + word(tracks[t + 5u + c]) * (float(readBits(base, at, bits)) / top);
  return v;
}

// Three of x, y, z, w stored, `dropped` (0 w, 1 x, 2 y, 3 z) rebuilt >= 0 (trackRotation).
vec4 rotationOf(vec3 s, uint dropped) {
  float rest = sqrt(max(1.0 - s.x * s.x - s.y * s.y - s.z * s.z, 0.0));
  vec4 q = dropped == 0u   ? vec4(s, rest)
           : dropped == 1u ? vec4(rest, s)
           : dropped == 2u ? vec4(s.x, rest, s.y, s.z)
                           : vec4(s.x, s.y, rest, s.z);
  return normalize(q); // x, y, z, w
}

vec4 slerpShorter(vec4 a, vec4 b, float s) {
  float d = dot(a, b);
  if (d < 0.0) {
    b = -b;
    d = -d;
  }
  if (d > 0.9998)
    return normalize(a * (1.0 - s) + b * s);
  float theta = acos(d), sn = sin(theta);
  return a * (sin((1.0 - s) * theta) / sn) + b * (sin(s * theta) / sn);
}

struct Trs {
  vec4 rotation;
  vec3 translation, scale;
};

// Node `node`'s local transform in clip `clip` at `span` (decodeLocalPose).
Trs localOf(uint clip, Span span, uint node) {
  uint r = node * kNodeWords + 2u;
  Trs trs = Trs(vec4(word(rig[r]), word(rig[r + 1u]), word(rig[r + 2u]), word(rig[r + 3u])),
                vec3(word(rig[r + 4u]), word(rig[r + 5u]), word(rig[r + 6u])),
                vec3(word(rig[r + 7u]), word(rig[r + 8u]), word(rig[r + 9u])));
  uint base = tracks[clip * kClipWords + 3u];
  for (uint p = 0u; p < 3u; ++p) {
    uint track = tracks[clip * kClipWords + 2u] + node * 3u + p;
    uint t = uint(u_clips) * kClipWords + track * kTrackWords;
    uint kind = tracks[t] & 0xffu;
    if (kind == 0u)
      continue;
    vec3 v;
    vec4 q;
    if (kind == 1u) {
      v = vec3(word(tracks[t + 2u]), word(tracks[t + 3u]), word(tracks[t + 4u]));
      q = rotationOf(v, 0u);
    } else {
      vec3 a = trackSample(track, base, span.first);
      bool hold = ((tracks[t] >> 8) & 0xffu) != 0u || span.first == span.second;
      vec3 b = hold ? a : trackSample(track, base, span.second);
      uint dropped = tracks[t] >> 24;
      if (p == 0u)
        q = hold ? rotationOf(a, dropped)
                 : slerpShorter(rotationOf(a, dropped), rotationOf(b, dropped), span.alpha);
      else
        v = mix(a, b, hold ? 0.0 : span.alpha);
    }
    if (p == 0u)
      trs.rotation = q;
    else if (p == 1u)
      trs.translation = v;
    else
      trs.scale = v;
  }
  return trs;
}

mat4 matrixOf(Trs t) {
  vec4 q = t.rotation;
  float x = q.x, y = q.y, z = q.z, w = q.w;
  return mat4(vec4(1.0 - 2.0 * (y * y + z * z), 2.0 * (x * y + w * z), 2.0 * (x * z - w * y), 0.0) *
                  t.scale.x,
              vec4(2.0 * (x * y - w * z), 1.0 - 2.0 * (x * x + z * z), 2.0 * (y * z + w * x), 0.0) *
                  t.scale.y,
              vec4(2.0 * (x * z + w * y), 2.0 * (y * z - w * x), 1.0 - 2.0 * (x * x + y * y), 0.0) *
                  t.scale.z,
              vec4(t.translation, 1.0));
}

void main() {
  uint request = gl_GlobalInvocationID.x;
  if (request >= uint(u_requests))
    return;
  vec4 now = requests[2u * request], blend = requests[2u * request + 1u];
  uint clip = uint(now.x);
  Span span = spanOf(clip, now.y);
  bool fading = now.z >= 0.0;
  uint fromClip = uint(max(now.z, 0.0));
  Span fromSpan = spanOf(fromClip, now.w);
  uint globalsBase = request * uint(u_nodes);
  for (uint n = 0u; n < uint(u_nodes); ++n) {
    mat4 local;
    uint r = n * kNodeWords;
    if (rig[r + 1u] != 0u) { // a rest matrix: 3 rows
      local = transpose(mat4(word(rig[r + 2u]), word(rig[r + 3u]), word(rig[r + 4u]), word(rig[r + 5u]),
                             word(rig[r + 6u]), word(rig[r + 7u]), word(rig[r + 8u]), word(rig[r + 9u]),
                             word(rig[r + 10u]), word(rig[r + 11u]), word(rig[r + 12u]),
                             word(rig[r + 13u]), 0.0, 0.0, 0.0, 1.0));
    } else {
      Trs t = localOf(clip, span, n);
      if (fading) {
        Trs f = localOf(fromClip, fromSpan, n);
        t = Trs(slerpShorter(f.rotation, t.rotation, blend.x), mix(f.translation, t.translation, blend.x),
                mix(f.scale, t.scale, blend.x));
      }
      local = matrixOf(t);
    }
    int parent = int(rig[r]);
    globals[globalsBase + n] = parent >= 0 ? globals[globalsBase + uint(parent)] * local : local;
  }
  for (uint j = 0u; j < uint(u_joints); ++j) {
    uint r = uint(u_nodes) * kNodeWords + j * kJointWords;
    mat4 inverseBind;
    for (uint k = 0u; k < 16u; ++k)
      inverseBind[k / 4u][k % 4u] = word(rig[r + 4u + k]);
    mat4 m = globals[globalsBase + rig[r]] * inverseBind;
    uint out0 = (request * uint(u_joints) + j) * 3u;
    palettes[out0] = vec4(m[0].x, m[1].x, m[2].x, m[3].x);
    palettes[out0 + 1u] = vec4(m[0].y, m[1].y, m[2].y, m[3].y);
    palettes[out0 + 2u] = vec4(m[0].z, m[1].z, m[2].z, m[3].z);
  }
}
