#include "crowd/formats/bytes.h"

namespace crowd::pack {

void ByteWriter::putString(const std::string &s) {
  put<uint32_t>(uint32_t(s.size()));
  bytes_.insert(bytes_.end(), s.begin(), s.end());
}

void ByteWriter::align(size_t to) {
  while (bytes_.size() % to != 0)
    bytes_.push_back(0);
}

std::string ByteReader::getString(const char *field) {
  uint32_t size = get<uint32_t>(field);
  need(size, field);
  std::string s(reinterpret_cast<const char *>(bytes_.data() + pos_), size);
  pos_ += size;
  return s;
}

void ByteReader::align(size_t to, const char *field) {
  size_t padded = (pos_ + to - 1) / to * to;
  need(padded - pos_, field);
  pos_ = padded;
}

void ByteReader::expectEnd() {
  if (pos_ != bytes_.size())
    fail("end", std::to_string(bytes_.size() - pos_) + " unexpected trailing bytes");
}

void ByteReader::need(size_t n, const char *field) const {
  if (n > bytes_.size() - pos_)
    fail(field, "needs " + std::to_string(n) + " bytes at offset " + std::to_string(pos_) +
                    " but the chunk has " + std::to_string(bytes_.size()));
}

void ByteReader::fail(const char *field, const std::string &what) const {
  throw Error(context_ + ", field '" + field + "': " + what);
}

} // namespace crowd::pack
