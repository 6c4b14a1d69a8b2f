#include "crowd/runtime/pack_joints.h"

#include "crowd/runtime/track_palettes.h"

namespace crowd::runtime {

std::vector<JointRows> sampleJoints(const pack::AnimationPack &p, size_t clip, uint32_t frame,
                                    float alpha) {
  const pack::Clip &c = p.clips.at(clip);
  if (p.hasTexture())
    return sampleJoints(p.animation, c, frame, alpha);
  // The texture's frame f is the time f / fps into the clip (the clip table's rate).
  const float seconds = (float(frame) + alpha) / c.fps;
  const std::vector<glm::mat4> palette = decodePalette(p, {float(clip), seconds});
  std::vector<JointRows> rows(palette.size());
  for (size_t j = 0; j < palette.size(); ++j)
    rows[j] = toRows(palette[j]);
  return rows;
}

JointRows sampleJoint(const pack::AnimationPack &p, size_t clip, uint32_t frame, float alpha,
                      uint32_t joint) {
  if (p.hasTexture())
    return sampleJoint(p.animation, p.clips.at(clip), frame, alpha, joint);
  return sampleJoints(p, clip, frame, alpha).at(joint);
}

} // namespace crowd::runtime
