// The importer's animation stage (bake/src/import/gltf_animations.h) on samplers built by hand:
// each interpolation read, key times that repeat read as a step with a warning, times that
// decrease and values that do not fit their keys refused, key rotations normalised.
#include <gtest/gtest.h>

#include <cstring>
#include <string>
#include <vector>

#include "../../bake/src/import/gltf_animations.h"
#include "crowd/formats/error.h"

namespace {

using crowd::Channel;
using crowd::ChannelPath;
using crowd::Interpolation;

// A model whose accessor 0 holds the key times and accessor 1 the values (float, tightly packed).
struct Sampler {
  tinygltf::Model model;
  tinygltf::AnimationSampler sampler;
  std::string path = "hand.gltf", stage;
  crowd::Reporter reporter;

  Sampler(const std::vector<float> &times, const std::vector<float> &values, int valueType,
          const std::string &interpolation) {
    model.buffers.emplace_back();
    add(times, TINYGLTF_TYPE_SCALAR, times.size());
    const size_t per = size_t(valueType == TINYGLTF_TYPE_VEC4 ? 4 : 3);
    add(values, valueType, values.size() / per);
    sampler.input = 0;
    sampler.output = 1;
    sampler.interpolation = interpolation;
  }
  void add(const std::vector<float> &v, int type, size_t count) {
    auto &data = model.buffers[0].data;
    tinygltf::BufferView view;
    view.buffer = 0;
    view.byteOffset = data.size();
    view.byteLength = v.size() * sizeof(float);
    data.resize(data.size() + view.byteLength);
    if (!v.empty()) // memcpy from an empty vector's null data is undefined, even for 0 bytes
      std::memcpy(data.data() + view.byteOffset, v.data(), view.byteLength);
    model.bufferViews.push_back(view);
    tinygltf::Accessor a;
    a.bufferView = int(model.bufferViews.size() - 1);
    a.componentType = TINYGLTF_COMPONENT_TYPE_FLOAT;
    a.type = type;
    a.count = count;
    model.accessors.push_back(a);
  }
  // The channel read, or throws crowd::Error.
  Channel read(ChannelPath path) {
    crowd::gltf::Accessors accessors(model, this->path, stage);
    Channel out;
    out.path = path;
    crowd::gltf::readSamplerKeys(sampler, accessors, this->path, "channel 0", reporter, out);
    return out;
  }
  std::string error(ChannelPath path) {
    try {
      read(path);
    } catch (const crowd::Error &e) {
      return e.what();
    }
    return "";
  }
};

TEST(GltfAnimations, EachInterpolationIsReadWithItsValuesPerKey) {
  Sampler linear({0, 1}, {0, 0, 0, 1, 2, 3}, TINYGLTF_TYPE_VEC3, ""); // LINEAR by default
  Channel c = linear.read(ChannelPath::Translation);
  EXPECT_EQ(c.interpolation, Interpolation::Linear);
  EXPECT_EQ(c.times, (std::vector<double>{0, 1}));
  EXPECT_EQ(c.values, (std::vector<double>{0, 0, 0, 1, 2, 3}));
  EXPECT_EQ(Sampler({0, 1}, {0, 0, 0, 1, 2, 3}, TINYGLTF_TYPE_VEC3, "STEP")
                .read(ChannelPath::Scale)
                .interpolation,
            Interpolation::Step);
  // A cubic spline holds in-tangent, value and out-tangent per key: 3 x 2 keys x 3.
  std::vector<float> spline(18, 0.5f);
  EXPECT_EQ(Sampler({0, 1}, spline, TINYGLTF_TYPE_VEC3, "CUBICSPLINE")
                .read(ChannelPath::Translation)
                .interpolation,
            Interpolation::CubicSpline);
  // Without tangents the values do not fit the keys.
  EXPECT_EQ(Sampler({0, 1}, {0, 0, 0, 1, 2, 3}, TINYGLTF_TYPE_VEC3, "CUBICSPLINE")
                .error(ChannelPath::Translation),
            "hand.gltf: channel 0 output: 6 values for 2 keys of 9");
  EXPECT_EQ(Sampler({0, 1}, {0, 0, 0, 1, 2, 3}, TINYGLTF_TYPE_VEC3, "SMOOTH")
                .error(ChannelPath::Translation),
            "hand.gltf: channel 0: unknown interpolation 'SMOOTH'");
}

TEST(GltfAnimations, RepeatedKeyTimesAreStepsWithAWarningAndDecreasingTimesFail) {
  Sampler repeated({0, 1, 1, 2}, std::vector<float>(12, 1.0f), TINYGLTF_TYPE_VEC3, "LINEAR");
  EXPECT_EQ(repeated.read(ChannelPath::Translation).times, (std::vector<double>{0, 1, 1, 2}));
  ASSERT_EQ(repeated.reporter.warnings().size(), 1u);
  EXPECT_EQ(repeated.reporter.warnings()[0].code, "keys_at_one_time");
  EXPECT_EQ(repeated.reporter.warnings()[0].count, 1u);

  Sampler decreasing({0, 2, 1}, std::vector<float>(9, 1.0f), TINYGLTF_TYPE_VEC3, "LINEAR");
  EXPECT_EQ(decreasing.error(ChannelPath::Translation),
            "hand.gltf: channel 0 input: key times decrease at key 2");
  EXPECT_EQ(Sampler({}, {}, TINYGLTF_TYPE_VEC3, "LINEAR").error(ChannelPath::Translation),
            "hand.gltf: channel 0: sampler has no keyframes");
}

TEST(GltfAnimations, KeyRotationsAreNormalisedButSplineTangentsAreNot) {
  // 16-bit quantised keys are off unit length: normalised; one within 1e-6 is left as it is.
  Sampler rotation({0, 1}, {0, 0, 0, 2, 0, 0.6f, 0, 0.8f}, TINYGLTF_TYPE_VEC4, "LINEAR");
  const Channel r = rotation.read(ChannelPath::Rotation);
  EXPECT_EQ(r.components, 4u);
  EXPECT_EQ(r.values[3], 1.0);
  EXPECT_EQ(r.values[5], double(0.6f)); // |(0, 0.6f, 0, 0.8f)| is within 1e-6 of 1: untouched
  std::vector<float> spline(24, 2.0f);
  const Channel s =
      Sampler({0, 1}, spline, TINYGLTF_TYPE_VEC4, "CUBICSPLINE").read(ChannelPath::Rotation);
  EXPECT_EQ(s.values, std::vector<double>(24, 2.0));
}

} // namespace
