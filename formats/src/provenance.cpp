// The PROV chunk: the baker version, its settings and a hash of every input file.
#include "crowd/formats/chunks.h"

#include <algorithm>
#include <cmath>
#include <cstring>

#include "chunk_checks.h"
#include "crowd/formats/bytes.h"
#include "crowd/formats/error.h"

namespace crowd::pack {

using namespace checks;

std::vector<uint8_t> encode(const Provenance &p) {
  ByteWriter w;
  w.putString(p.bakerVersion);
  w.put<uint32_t>(uint32_t(p.settings.size()));
  for (const auto &[k, v] : p.settings) {
    w.putString(k);
    w.putString(v);
  }
  w.put<uint32_t>(uint32_t(p.inputs.size()));
  for (const auto &in : p.inputs) {
    w.putString(in.path);
    w.put<uint64_t>(in.size);
    w.putString(in.hash);
  }
  return w.take();
}

Provenance decodeProvenance(std::span<const uint8_t> bytes, const std::string &context) {
  ByteReader r(bytes, context);
  Provenance p;
  p.bakerVersion = r.getString("baker version");
  uint32_t n = r.get<uint32_t>("settings count");
  for (uint32_t i = 0; i < n; ++i) {
    std::string k = r.getString("setting name");
    p.settings.emplace_back(k, r.getString("setting value"));
  }
  n = r.get<uint32_t>("input count");
  for (uint32_t i = 0; i < n; ++i) {
    InputFile in;
    in.path = r.getString("input path");
    in.size = r.get<uint64_t>("input size");
    in.hash = r.getString("input hash");
    p.inputs.push_back(in);
  }
  r.expectEnd();
  return p;
}

} // namespace crowd::pack
