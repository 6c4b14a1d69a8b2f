// The importer's accessor stage (bake/src/import/gltf_accessors.h) on models built by hand: the
// specification's layout (byteStride, normalised integers, sparse substitution) read exactly, and
// every range that would read outside a buffer refused with the file and the accessor named.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <limits>
#include <string>
#include <vector>

#include "../../bake/src/import/gltf_accessors.h"
#include "crowd/formats/error.h"
#include "crowd/formats/limits.h"

namespace {

// One buffer, and in it one view per call to addView; accessors over those views.
struct Model {
  tinygltf::Model m;
  Model() { m.buffers.emplace_back(); }

  template <class T> int addView(const std::vector<T> &values, int stride = 0) {
    auto &data = m.buffers[0].data;
    tinygltf::BufferView view;
    view.buffer = 0;
    view.byteOffset = data.size();
    view.byteLength = values.size() * sizeof(T);
    view.byteStride = size_t(stride);
    data.resize(data.size() + view.byteLength);
    if (!values.empty()) // memcpy from an empty vector's null data is undefined, even for 0 bytes
      std::memcpy(data.data() + view.byteOffset, values.data(), view.byteLength);
    m.bufferViews.push_back(view);
    return int(m.bufferViews.size() - 1);
  }
  int addAccessor(int view, int componentType, int type, size_t count, bool normalized = false) {
    tinygltf::Accessor a;
    a.bufferView = view;
    a.componentType = componentType;
    a.type = type;
    a.count = count;
    a.normalized = normalized;
    m.accessors.push_back(a);
    return int(m.accessors.size() - 1);
  }
};

struct Reading {
  std::string path = "hand.gltf", stage;
  crowd::gltf::Accessors accessors;
  explicit Reading(const Model &model) : accessors(model.m, path, stage) {}
  // The error reading accessor `index` gives, or "" where it reads.
  std::string error(int index, bool finite = true) {
    try {
      accessors.read(index, "test", finite);
    } catch (const crowd::Error &e) {
      return e.what();
    }
    return "";
  }
};

TEST(GltfAccessors, NormalisedIntegersAcrossAStrideReadAsTheSpecificationSays) {
  Model model;
  // UNSIGNED_BYTE VEC2 at a 4-byte stride: two bytes of every four are padding.
  const int bytes = model.addView<uint8_t>({255, 0, 9, 9, 128, 51, 9, 9}, 4);
  const int ub =
      model.addAccessor(bytes, TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE, TINYGLTF_TYPE_VEC2, 2, true);
  // Signed: the most negative value clamps to -1 (max(c / 127, -1)).
  const int shorts = model.addView<int16_t>({-32768, 32767, -16384});
  const int ss =
      model.addAccessor(shorts, TINYGLTF_COMPONENT_TYPE_SHORT, TINYGLTF_TYPE_SCALAR, 3, true);
  const int sb = model.addAccessor(model.addView<int8_t>({-128, 127}), TINYGLTF_COMPONENT_TYPE_BYTE,
                                   TINYGLTF_TYPE_SCALAR, 2, true);
  // Not normalised: the integers as they are.
  const int raw = model.addAccessor(shorts, TINYGLTF_COMPONENT_TYPE_SHORT, TINYGLTF_TYPE_SCALAR, 3);
  Reading r(model);
  EXPECT_EQ(*r.accessors.read(ub, "uv"), (std::vector<double>{1.0, 0.0, 128 / 255.0, 0.2}));
  EXPECT_EQ(*r.accessors.read(ss, "w"), (std::vector<double>{-1.0, 1.0, -16384 / 32767.0}));
  EXPECT_EQ(*r.accessors.read(sb, "w"), (std::vector<double>{-1.0, 1.0}));
  EXPECT_EQ(*r.accessors.read(raw, "j"), (std::vector<double>{-32768, 32767, -16384}));
}

TEST(GltfAccessors, SparseValuesReplaceTheirElementsOverZerosOrAView) {
  Model model;
  // No bufferView: zeros, then two sparse values at elements 3 and 1.
  const int acc = model.addAccessor(-1, TINYGLTF_COMPONENT_TYPE_FLOAT, TINYGLTF_TYPE_SCALAR, 4);
  auto &sparse = model.m.accessors[size_t(acc)].sparse;
  sparse.isSparse = true;
  sparse.count = 2;
  sparse.indices.byteOffset = sparse.values.byteOffset = 0; // tinygltf leaves them unset
  sparse.indices.bufferView = model.addView<uint16_t>({3, 1});
  sparse.indices.componentType = TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT;
  sparse.values.bufferView = model.addView<float>({7, 5});
  Reading r(model);
  EXPECT_EQ(*r.accessors.read(acc, "morph"), (std::vector<double>{0, 5, 0, 7}));

  // An index past the accessor's count is refused, not written past the vector.
  Model bad = model;
  bad.m.accessors[0].sparse.indices.bufferView = bad.addView<uint16_t>({4, 1});
  EXPECT_NE(Reading(bad).error(0).find("sparse index out of range"), std::string::npos);
}

TEST(GltfAccessors, EveryRangeOutsideItsViewOrBufferIsRefusedNamingFileAndAccessor) {
  Model model;
  const int view = model.addView<float>({1, 2, 3, 4, 5, 6});
  // 3 VEC2 fill the view exactly; a fourth runs past it.
  model.addAccessor(view, TINYGLTF_COMPONENT_TYPE_FLOAT, TINYGLTF_TYPE_VEC2, 3);
  model.addAccessor(view, TINYGLTF_COMPONENT_TYPE_FLOAT, TINYGLTF_TYPE_VEC2, 4);
  Reading r(model);
  EXPECT_EQ(r.error(0), "");
  EXPECT_EQ(r.error(1), "hand.gltf: test, accessor 1: 4 elements run past the end of bufferView 0");

  Model stride = model; // a stride shorter than the element would read elements overlapping
  stride.m.bufferViews[0].byteStride = 4;
  EXPECT_NE(Reading(stride).error(0).find("byteStride 4 is smaller than an element (8 bytes)"),
            std::string::npos);

  Model outside = model; // the view itself past its buffer's end
  outside.m.bufferViews[0].byteLength = 28;
  EXPECT_NE(Reading(outside).error(0).find("bufferView 0 lies outside buffer 0 (24 bytes)"),
            std::string::npos);

  Model missing = model;
  missing.m.bufferViews[0].buffer = 3;
  EXPECT_NE(Reading(missing).error(0).find("buffer 3 does not exist"), std::string::npos);
  EXPECT_NE(r.error(7).find("test, accessor 7: does not exist"), std::string::npos);

  // A count over the limit fails before its elements are allocated (2^24 + 1 VEC4 of nothing).
  model.addAccessor(-1, TINYGLTF_COMPONENT_TYPE_FLOAT, TINYGLTF_TYPE_VEC4,
                    crowd::limits::kAccessorElements + 1);
  EXPECT_NE(Reading(model).error(2).find("is over the limit of 16777216 elements"),
            std::string::npos);
}

TEST(GltfAccessors, NonFiniteValuesFailWhereAskedAndAReadIsShared) {
  Model model;
  const float nan = std::numeric_limits<float>::quiet_NaN();
  const int acc = model.addAccessor(model.addView<float>({0, nan, 2}),
                                    TINYGLTF_COMPONENT_TYPE_FLOAT, TINYGLTF_TYPE_SCALAR, 3);
  Reading r(model);
  EXPECT_EQ(r.error(acc), "hand.gltf: test, accessor 0: element 1 is NaN or infinite");
  EXPECT_EQ(r.stage, "reading test, accessor 0"); // what an out-of-memory error would name
  const auto kept = r.accessors.read(acc, "morph", false);
  EXPECT_TRUE(std::isnan((*kept)[1]));
  // Several primitives share one accessor: read once, the same elements handed to each.
  EXPECT_EQ(r.accessors.read(acc, "again", false), kept);
  EXPECT_EQ(r.accessors.count(acc), 3u);
  EXPECT_EQ(r.accessors.type(acc, "test"), TINYGLTF_TYPE_SCALAR);
}

} // namespace
