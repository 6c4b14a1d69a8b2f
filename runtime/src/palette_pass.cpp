#include "crowd/runtime/palette_pass.h"

#include <cstring>
#include <unordered_map>

#include <epoxy/gl.h>

namespace crowd::runtime {

namespace {

constexpr unsigned kWorkGroup = 32; // palette.comp's local_size_x

struct RequestHash {
  size_t operator()(const PaletteRequest &r) const {
    uint32_t w[5];
    std::memcpy(&w[0], &r.clip, 4);
    std::memcpy(&w[1], &r.seconds, 4);
    std::memcpy(&w[2], &r.from, 4);
    std::memcpy(&w[3], &r.fromSeconds, 4);
    std::memcpy(&w[4], &r.weight, 4);
    size_t h = 0;
    for (uint32_t x : w)
      h = h * 0x9e3779b97f4a7c15ull + x;
    return h;
  }
};

} // namespace

PalettePass::PalettePass(const pack::AnimationPack &p, uint32_t instances, float slot)
    : pack_(&p), slots_(paletteSlots(p, slot)) {
  const TrackWords w = trackWords(p);
  nodes_ = w.nodes, joints_ = w.joints, clips_ = w.clips;
  glCreateBuffers(GLsizei(std::size(buffers_)), buffers_);
  glGenQueries(2, queries_);
  auto upload = [](unsigned b, const auto &v) {
    glNamedBufferStorage(b, GLsizeiptr(v.size() * sizeof(v[0])), v.data(), 0);
  };
  upload(buffers_[0], w.rig);
  upload(buffers_[1], w.tracks);
  upload(buffers_[2], w.times);
  upload(buffers_[3], w.stream);
  paletteOf_.assign(std::max(instances, 1u), 0);
  glNamedBufferStorage(buffers_[7], GLsizeiptr(paletteOf_.size() * 4), nullptr,
                       GL_DYNAMIC_STORAGE_BIT);
}

PalettePass::~PalettePass() {
  glDeleteBuffers(GLsizei(std::size(buffers_)), buffers_);
  glDeleteQueries(2, queries_);
}

uint32_t PalettePass::run(unsigned program, const std::vector<float> &instanceData, size_t stride,
                          const std::vector<uint32_t> &ids, float seconds, bool timed) {
  timed_ = false;
  requests_.clear();
  std::unordered_map<PaletteRequest, int32_t, RequestHash> index; // looked up, never iterated
  for (uint32_t i : ids) {
    const float *d = &instanceData[size_t(i) * stride + 12];
    const PaletteRequest r =
        paletteRequest(*pack_, {d[0], d[1], d[2], d[3]}, {d[4], d[5], d[6], d[7]}, seconds, slots_);
    auto [it, added] = index.try_emplace(r, int32_t(requests_.size()));
    if (added)
      requests_.push_back(r);
    paletteOf_[i] = it->second;
  }
  const uint32_t count = uint32_t(requests_.size());
  if (count == 0)
    return 0;
  if (count > capacity_) { // grown as needed: a frame asks at most one palette per instance
    capacity_ = std::max(count, capacity_ * 2);
    glNamedBufferData(buffers_[4], GLsizeiptr(capacity_) * 32, nullptr, GL_DYNAMIC_DRAW);
    glNamedBufferData(buffers_[5], GLsizeiptr(capacity_) * joints_ * 48, nullptr, GL_DYNAMIC_COPY);
    glNamedBufferData(buffers_[6], GLsizeiptr(capacity_) * nodes_ * 64, nullptr, GL_DYNAMIC_COPY);
  }
  std::vector<float> words;
  words.reserve(size_t(count) * 8);
  for (const PaletteRequest &r : requests_)
    words.insert(words.end(), {r.clip, r.seconds, r.from, r.fromSeconds, r.weight, 0, 0, 0});
  glNamedBufferSubData(buffers_[4], 0, GLsizeiptr(words.size() * 4), words.data());
  glNamedBufferSubData(buffers_[7], 0, GLsizeiptr(paletteOf_.size() * 4), paletteOf_.data());
  glUseProgram(program);
  glUniform1i(glGetUniformLocation(program, "u_requests"), int(count));
  glUniform1i(glGetUniformLocation(program, "u_nodes"), int(nodes_));
  glUniform1i(glGetUniformLocation(program, "u_joints"), int(joints_));
  glUniform1i(glGetUniformLocation(program, "u_clips"), int(clips_));
  glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 0, buffers_[4]);
  for (unsigned b = 0; b < 4; ++b)
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 1 + b, buffers_[b]);
  glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 5, buffers_[5]);
  glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 6, buffers_[6]);
  if (timed)
    glQueryCounter(queries_[0], GL_TIMESTAMP);
  glDispatchCompute((count + kWorkGroup - 1) / kWorkGroup, 1, 1);
  glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT);
  if (timed)
    glQueryCounter(queries_[1], GL_TIMESTAMP);
  timed_ = timed;
  return count;
}

double PalettePass::gpuMilliseconds() const {
  if (!timed_)
    return 0;
  GLuint64 t[2] = {0, 0};
  glGetQueryObjectui64v(queries_[0], GL_QUERY_RESULT, &t[0]);
  glGetQueryObjectui64v(queries_[1], GL_QUERY_RESULT, &t[1]);
  return double(t[1] - t[0]) / 1e6;
}

void PalettePass::bind() const {
  glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 9, buffers_[5]);
  glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 10, buffers_[7]);
}

} // namespace crowd::runtime
