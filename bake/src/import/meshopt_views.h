// glTF files as web pipelines write them (gltfpack -c / -cc): buffer views compressed with
// EXT_meshopt_compression or KHR_meshopt_compression, decoded with meshoptimizer's decoders
// before tinygltf reads the file. Every field of a compressed view is checked against its source
// buffer and the limits first; a stream in a codec version the linked meshoptimizer cannot
// decode, a filter it lacks and a stream that does not decode are errors naming the view.
#pragma once
#include <cstdint>
#include <functional>
#include <string>
#include <vector>

namespace crowd {

// The bytes of an external buffer, by its URI as the glTF writes it (the caller confines it).
using ReadBufferUri = std::function<std::vector<uint8_t>(const std::string &uri)>;

// When the glTF (`bytes`: .gltf JSON or .glb) uses meshopt compression, replaces `bytes` with a
// GLB holding the same glTF with every compressed view decoded into its binary chunk and the
// extension gone, and returns true; otherwise leaves `bytes` and returns false. Throws
// crowd::Error prefixed by `path`.
bool decodeMeshoptViews(std::vector<uint8_t> &bytes, const std::string &path,
                        const ReadBufferUri &readUri);

} // namespace crowd
