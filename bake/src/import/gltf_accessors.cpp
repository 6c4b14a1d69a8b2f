#include "gltf_accessors.h"

#include <algorithm>
#include <cmath>
#include <cstring>

#include "crowd/formats/error.h"
#include "crowd/formats/limits.h"

namespace crowd::gltf {
namespace {

int components(int type) {
  switch (type) {
  case TINYGLTF_TYPE_SCALAR:
    return 1;
  case TINYGLTF_TYPE_VEC2:
    return 2;
  case TINYGLTF_TYPE_VEC3:
    return 3;
  case TINYGLTF_TYPE_VEC4:
    return 4;
  case TINYGLTF_TYPE_MAT2:
    return 4;
  case TINYGLTF_TYPE_MAT3:
    return 9;
  case TINYGLTF_TYPE_MAT4:
    return 16;
  default:
    return 0;
  }
}

double readComponent(const uint8_t *p, int componentType, bool normalized) {
  switch (componentType) {
  case TINYGLTF_COMPONENT_TYPE_BYTE: {
    int8_t v;
    std::memcpy(&v, p, 1);
    return normalized ? std::max(v / 127.0, -1.0) : v;
  }
  case TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE:
    return normalized ? *p / 255.0 : *p;
  case TINYGLTF_COMPONENT_TYPE_SHORT: {
    int16_t v;
    std::memcpy(&v, p, 2);
    return normalized ? std::max(v / 32767.0, -1.0) : v;
  }
  case TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT: {
    uint16_t v;
    std::memcpy(&v, p, 2);
    return normalized ? v / 65535.0 : v;
  }
  case TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT: {
    uint32_t v;
    std::memcpy(&v, p, 4);
    return v;
  }
  default: {
    float v;
    std::memcpy(&v, p, 4);
    return v;
  }
  }
}

int componentSize(int componentType) {
  switch (componentType) {
  case TINYGLTF_COMPONENT_TYPE_BYTE:
  case TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE:
    return 1;
  case TINYGLTF_COMPONENT_TYPE_SHORT:
  case TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT:
    return 2;
  case TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT:
  case TINYGLTF_COMPONENT_TYPE_FLOAT:
    return 4;
  default:
    return 0;
  }
}

} // namespace

void Accessors::fail(const std::string &what) const { throw Error(path_ + ": " + what); }

const uint8_t *Accessors::viewRange(int view, size_t offset, size_t count, size_t stride,
                                    size_t elemSize, const std::string &what) const {
  if (view < 0 || size_t(view) >= model_.bufferViews.size())
    fail(what + ": bufferView " + std::to_string(view) + " does not exist");
  const auto &bv = model_.bufferViews[size_t(view)];
  if (bv.buffer < 0 || size_t(bv.buffer) >= model_.buffers.size())
    fail(what + ": buffer " + std::to_string(bv.buffer) + " does not exist");
  const auto &buf = model_.buffers[size_t(bv.buffer)].data;
  if (bv.byteOffset > buf.size() || bv.byteLength > buf.size() - bv.byteOffset)
    fail(what + ": bufferView " + std::to_string(view) + " lies outside buffer " +
         std::to_string(bv.buffer) + " (" + std::to_string(buf.size()) + " bytes)");
  if (count > 0) {
    // Division avoids overflow on absurd counts.
    if (offset > bv.byteLength || elemSize > bv.byteLength - offset ||
        (count - 1) > (bv.byteLength - offset - elemSize) / stride)
      fail(what + ": " + std::to_string(count) + " elements run past the end of bufferView " +
           std::to_string(view));
  }
  return buf.data() + bv.byteOffset + offset;
}

std::shared_ptr<const std::vector<double>> Accessors::read(int index, const std::string &what,
                                                           bool finite) {
  auto cached = cache_.find({index, finite});
  if (cached != cache_.end())
    return cached->second;
  std::string ctx = what + ", accessor " + std::to_string(index);
  stage_ = "reading " + ctx;
  if (index < 0 || size_t(index) >= model_.accessors.size())
    fail(ctx + ": does not exist");
  const auto &acc = model_.accessors[size_t(index)];
  int nc = components(acc.type);
  int cs = componentSize(acc.componentType);
  if (nc == 0 || cs == 0)
    fail(ctx + ": unsupported type or component type");
  if (acc.count > limits::kAccessorElements)
    fail(ctx + ": count " + std::to_string(acc.count) + " is over the limit of " +
         std::to_string(limits::kAccessorElements) + " elements");
  size_t elemSize = size_t(nc) * size_t(cs);
  const uint8_t *p = nullptr;
  size_t stride = elemSize;
  if (acc.bufferView >= 0) {
    if (size_t(acc.bufferView) < model_.bufferViews.size() &&
        model_.bufferViews[size_t(acc.bufferView)].byteStride) {
      stride = model_.bufferViews[size_t(acc.bufferView)].byteStride;
      if (stride < elemSize)
        fail(ctx + ": bufferView byteStride " + std::to_string(stride) +
             " is smaller than an element (" + std::to_string(elemSize) + " bytes)");
    }
    p = viewRange(acc.bufferView, acc.byteOffset, acc.count, stride, elemSize, ctx);
  }
  auto shared = std::make_shared<std::vector<double>>(acc.count * size_t(nc), 0.0);
  auto &out = *shared;
  if (p)
    for (size_t i = 0; i < acc.count; ++i)
      for (int c = 0; c < nc; ++c)
        out[i * size_t(nc) + size_t(c)] =
            readComponent(p + i * stride + size_t(c * cs), acc.componentType, acc.normalized);
  if (acc.sparse.isSparse) {
    size_t n = size_t(std::max(acc.sparse.count, 0));
    int ics = componentSize(acc.sparse.indices.componentType);
    if (ics == 0 || n > acc.count)
      fail(ctx + ": bad sparse block");
    const uint8_t *ip =
        viewRange(acc.sparse.indices.bufferView, size_t(std::max(acc.sparse.indices.byteOffset, 0)),
                  n, size_t(ics), size_t(ics), ctx + " sparse indices");
    const uint8_t *vp =
        viewRange(acc.sparse.values.bufferView, size_t(std::max(acc.sparse.values.byteOffset, 0)),
                  n, elemSize, elemSize, ctx + " sparse values");
    for (size_t k = 0; k < n; ++k) {
      auto target =
          size_t(readComponent(ip + k * size_t(ics), acc.sparse.indices.componentType, false));
      if (target >= acc.count)
        fail(ctx + ": sparse index out of range");
      for (int c = 0; c < nc; ++c)
        out[target * size_t(nc) + size_t(c)] =
            readComponent(vp + k * elemSize + size_t(c * cs), acc.componentType, acc.normalized);
    }
  }
  if (finite)
    for (size_t i = 0; i < out.size(); ++i)
      if (!std::isfinite(out[i]))
        fail(ctx + ": element " + std::to_string(i / size_t(nc)) + " is NaN or infinite");
  cache_[{index, finite}] = shared;
  return shared;
}

size_t Accessors::count(int index) const {
  if (index < 0 || size_t(index) >= model_.accessors.size())
    fail("accessor " + std::to_string(index) + ": does not exist");
  return model_.accessors[size_t(index)].count;
}
int Accessors::type(int index, const std::string &what) const {
  if (index < 0 || size_t(index) >= model_.accessors.size())
    fail(what + ", accessor " + std::to_string(index) + ": does not exist");
  return model_.accessors[size_t(index)].type;
}

} // namespace crowd::gltf
