// The crowd_oiio module: images.h's calls on OpenImageIO (see images.h for why a module).
#include <OpenImageIO/filesystem.h>
#include <OpenImageIO/imageio.h>

#include "image_codec.h"
#include "png_check.h"

namespace crowd::images {
namespace {

OIIO::TypeDesc typeOf(pack::Image::Pixel pixel) {
  using Pixel = pack::Image::Pixel;
  return pixel == Pixel::U8    ? OIIO::TypeDesc::UINT8
         : pixel == Pixel::U16 ? OIIO::TypeDesc::UINT16
         : pixel == Pixel::F16 ? OIIO::TypeDesc::HALF
                               : OIIO::TypeDesc::FLOAT;
}

bool decode(const std::vector<uint8_t> &bytes, const std::string &name, int maxSide,
            pack::Image &out, std::string &why) try {
  if (isPng(bytes) && !pngIsWhole(bytes, maxSide, why)) {
    why = "cannot decode (" + why + ")";
    return false;
  }
  OIIO::Filesystem::IOMemReader memory(bytes.data(), bytes.size());
  auto in = OIIO::ImageInput::open(name, nullptr, &memory);
  if (!in) {
    why = "cannot decode (" + OIIO::geterror() + ")";
    return false;
  }
  const auto &spec = in->spec();
  if (spec.width <= 0 || spec.height <= 0 || spec.width > maxSide || spec.height > maxSide) {
    why = std::to_string(spec.width) + "x" + std::to_string(spec.height) + " is outside 1.." +
          std::to_string(maxSide);
    return false;
  }
  if (spec.nchannels < 1) {
    why = "an image without channels";
    return false;
  }
  out.width = uint32_t(spec.width), out.height = uint32_t(spec.height);
  out.channels = uint32_t(spec.nchannels);
  out.pixel = pack::Image::Pixel::U8;
  out.bytes.assign(size_t(out.width) * out.height * out.channels, 0);
  if (!in->read_image(0, 0, 0, spec.nchannels, OIIO::TypeDesc::UINT8, out.bytes.data())) {
    why = "cannot decode (" + in->geterror() + ")";
    return false;
  }
  return true;
} catch (const std::exception &e) {
  why = std::string("cannot decode (") + e.what() + ")";
  return false;
}

// Writes through `out` opened on `path` (a file, or a name when an I/O proxy is set).
bool writeWith(OIIO::ImageOutput *out, const std::string &path, const pack::Image &image,
               OIIO::Filesystem::IOProxy *proxy, std::string &why) {
  const OIIO::TypeDesc type = typeOf(image.pixel);
  OIIO::ImageSpec spec(int(image.width), int(image.height), int(image.channels), type);
  spec.attribute("compression", "zip");
  if (!out || (proxy && !out->set_ioproxy(proxy)) || !out->open(path, spec) ||
      !out->write_image(type, image.bytes.data()) || !out->close()) {
    why = out ? out->geterror() : OIIO::geterror();
    return false;
  }
  return true;
}

bool write(const std::string &path, const pack::Image &image, std::string &why) try {
  auto out = OIIO::ImageOutput::create(path);
  return writeWith(out.get(), path, image, nullptr, why);
} catch (const std::exception &e) {
  why = e.what();
  return false;
}

bool encodePng(const pack::Image &image, std::vector<uint8_t> &bytes, std::string &why) try {
  bytes.clear();
  OIIO::Filesystem::IOVecOutput proxy(bytes);
  auto out = OIIO::ImageOutput::create("png");
  return writeWith(out.get(), "image.png", image, &proxy, why);
} catch (const std::exception &e) {
  why = e.what();
  return false;
}

const Codec kCodec = {decode, write, encodePng};

} // namespace
} // namespace crowd::images

extern "C" const crowd::images::Codec *crowd_image_codec() { return &crowd::images::kCodec; }
