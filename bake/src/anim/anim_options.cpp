// The animation bake's options and their checks (a manifest's reader needs these alone).
#include "crowd/bake/anim_bake.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>

#include "crowd/bake/anim_frames.h"
#include "crowd/bake/track_compression.h"
#include "crowd/formats/error.h"
#include "crowd/formats/limits.h"

namespace crowd {

const std::vector<Precision> &precisions() {
  using E = pack::JointEncoding;
  using F = pack::TexelFormat;
  static const std::vector<Precision> all = {{"float", E::Matrix3x4, F::RGBA32F},
                                             {"half", E::Matrix3x4, F::RGBA16F},
                                             {"qts", E::QuatTransScale, F::RGBA32F},
                                             {"qts-half", E::QuatTransScale, F::RGBA16F}};
  return all;
}

std::string errorBudgetProblem(double mm) {
  if (mm > 0 && mm <= kMaxErrorBudgetMm) // false for NaN
    return "";
  char text[96];
  std::snprintf(text, sizeof text, "%g is outside (0, %.0f] millimetres", mm, kMaxErrorBudgetMm);
  return text;
}

const Precision &precisionByName(const std::string &name) {
  for (const auto &p : precisions())
    if (p.name == name)
      return p;
  throw Error("unknown precision '" + name + "' (float, half, qts, qts-half)");
}

void AnimBakeOptions::validate() const {
  if (!(fps == kFpsFromBudget || (fps >= 0 && fps <= 1000)))
    throw Error("fps: must be in (0, 1000], source or auto");
  if (maxWidth < 2 || maxWidth > limits::kTextureSide)
    throw Error("max-width: must be in [2, " + std::to_string(limits::kTextureSide) + "]");
  if (threads < 0 || threads > 1024)
    throw Error("threads: must be in [0, 1024]");
  if (const std::string problem = errorBudgetProblem(errorBudgetMm); !problem.empty())
    throw Error("error-budget: " + problem);
  if (precision != "auto")
    try {
      precisionByName(precision);
    } catch (const Error &e) {
      throw Error(std::string("precision: ") + e.what() + " or auto");
    }
  const auto &all = stores();
  if (std::find(all.begin(), all.end(), store) == all.end())
    throw Error("store: '" + store + "' is none of texture, tracks, both or auto");
  if (store == "tracks" && precision != "auto")
    throw Error("precision: " + precision +
                " shapes the texture, which store tracks leaves out: drop the precision, or "
                "store texture, both or auto");
}

std::string AnimBakeOptions::shapesTheTexture() const {
  if (precision != "auto")
    return "precision " + precision;
  if (fps != kFpsFromBudget)
    return "fps " + fpsName(fps);
  return "";
}

std::string AnimBakeOptions::storeAsked(std::string *reason) const {
  const std::string option = shapesTheTexture();
  if (store != "auto" || option.empty())
    return store;
  if (reason)
    *reason = option + " shapes the texture: the texture is stored, no tracks compressed (store "
                       "auto; store both keeps the tracks too)";
  return "texture";
}

const std::vector<std::string> &AnimBakeOptions::stores() {
  static const std::vector<std::string> names = {"texture", "tracks", "both", "auto"};
  return names;
}

void TrackCompressionOptions::validate() const {
  if (const std::string problem = errorBudgetProblem(errorBudgetMm); !problem.empty())
    throw Error("errorBudgetMm: " + problem);
  if (!(mmPerUnit > 0) || !std::isfinite(mmPerUnit))
    throw Error("mmPerUnit: " + std::to_string(mmPerUnit) + " is not a positive number");
  if (threads < 0)
    throw Error("threads: " + std::to_string(threads) + " is negative");
}

double AnimBakeOptions::parseFps(const std::string &text) {
  if (text == "auto")
    return kFpsFromBudget;
  if (text == "source")
    return kFpsSource;
  try {
    size_t used = 0;
    const double fps = std::stod(text, &used);
    if (used == text.size() && fps > 0 && fps <= 1000)
      return fps;
  } catch (const std::exception &) {
  }
  throw Error("fps: expects auto, source or a number in (0, 1000], got '" + text + "'");
}

std::string AnimBakeOptions::fpsName(double fps) {
  if (fps == kFpsFromBudget)
    return "auto";
  if (fps == kFpsSource)
    return "source";
  std::string s = std::to_string(fps);
  s.erase(s.find_last_not_of('0') + 1);
  if (s.back() == '.')
    s.pop_back();
  return s;
}

} // namespace crowd
