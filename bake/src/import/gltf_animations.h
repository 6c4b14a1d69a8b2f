// The importer's animation stage: one sampler's keys as a Channel, checked as the glTF 2.0
// specification asks (a known interpolation, increasing key times, one value per key and
// component, three for a cubic spline); what it repairs is a warning.
#pragma once
#include <string>

#include <tiny_gltf.h>

#include "crowd/bake/character.h"
#include "crowd/bake/report.h"
#include "gltf_accessors.h"

namespace crowd::gltf {

// Sampler `s`'s interpolation, times and values into `out`, whose path is set (and for morph
// weights its components). Two keys at one time read as a step (the later holds from that
// time), with a warning; key rotations are normalised (a cubic spline's values hold tangents
// and are left). Errors start with `file`: `ctx` names the channel.
void readSamplerKeys(const tinygltf::AnimationSampler &s, Accessors &accessors,
                     const std::string &file, const std::string &ctx, Reporter &reporter,
                     Channel &out);

} // namespace crowd::gltf
