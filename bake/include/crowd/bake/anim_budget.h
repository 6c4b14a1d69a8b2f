// The error budget of the animation bake: per clip the frame rate, and for the pack the stored
// precision, with the fewest bytes whose largest error at any time (mid-frames and the seeded
// random times, where between-frame blending errs most, and the frame times, where a compact
// precision errs most) stays within the budget.
#pragma once
#include <array>
#include <string>
#include <vector>

#include "crowd/bake/anim_frames.h"
#include "crowd/bake/character.h"
#include "crowd/bake/report.h"

namespace crowd {

// Rates tried, lowest first; each clip also tries its source rate (frames on its keys). The top
// rates are for fast motion: the player blends each joint's global transform between frames,
// and the source composes local rotations, so they part by the square of the angle a frame
// turns (Fox's Run: 1.3 mm at 120 fps, about 0.3 at 240).
inline constexpr std::array<double, 12> kRateLadder = {10, 15, 20, 24,  30,  40,
                                                       48, 60, 90, 120, 180, 240};

// The error budgets a bake takes, millimetres at a 1.8 m character: above 0, at most this.
inline constexpr double kMaxErrorBudgetMm = 1e6;
// Empty where `mm` is such a budget, else what is wrong ("must be in (0, 1e6] millimetres"):
// the one check of the CLI's --error-budget, a manifest's error_budget_mm and the bakes' options.
std::string errorBudgetProblem(double mm);

// One rate and precision tried for a clip.
struct BudgetOption {
  double fps = 0; // as adjusted to land on the clip's end
  std::string precision;
  uint32_t frames = 0;
  uint64_t bytes = 0;    // frames x (the joints' bytes + the morph slots' where targets exist)
  double maxErrorMm = 0; // at frame times, mid-frames and the seeded random times, at 1.8 m
  bool meets = false;
};

struct ClipBudget {
  std::string clip;
  double fps = 0;                  // the rate baked
  double sourceFps = 0;            // the clip's own key rate
  std::vector<BudgetOption> tried; // in the order tried
  bool capped = false; // higher rates not tried: they take BudgetSearch::fewerBytesThan or more
};

struct BudgetChoice {
  std::string precision;              // the one stored for the whole pack
  std::vector<uint32_t> matrixJoints; // stored as matrix rows by the quaternion precisions
  bool met = false;                   // every clip within the budget at that precision
  bool searched = false;              // by chooseByBudget (else forced: nothing tried)
  uint64_t bytes = 0;                 // the options chosen: every clip's frames, unpadded
  std::vector<ClipBudget> clips;      // one per clip given, in order
};

struct BudgetSearch {
  double budgetMm = 1.0;
  double mmPerUnit = 1.0;               // model units to millimetres at 1.8 m
  std::vector<double> rates;            // empty: kRateLadder plus each clip's source rate
  bool sourceRateOnly = false;          // each clip at its source rate alone
  std::vector<const Precision *> tried; // the precisions to try
  std::vector<uint32_t> matrixJoints;   // the quaternion precisions' (matrixJointsByBudget)
  uint32_t maxWidth = 4096;
  int threads = 0;
  Reporter::Listener step; // a line as each clip's search starts
  // Rates are tried only while the texture could take fewer bytes than this (the tracks', where
  // they meet the budget): a clip's rate whose frames at the smallest precision tried, with every
  // other clip at its fewest (fewestTextureBytes), take as many is not tried (ClipBudget::capped).
  uint64_t fewerBytesThan = UINT64_MAX;
};

// The joints the quaternion precisions store as matrix rows: those whose encoding alone would
// take half the budget (matrixJointsFor) at a frame of some clip at its source rate (at most
// the ladder's top), or of the rest pose without clips.
std::vector<uint32_t> matrixJointsByBudget(const Character &c,
                                           const std::vector<const AnimationClip *> &clips,
                                           double budgetMm, double mmPerUnit, int threads);

// For each precision, the lowest rate per clip that meets the budget (or, where none does, the
// most accurate rate tried); then the precision whose clips take the fewest bytes, among those
// meeting the budget on every clip (else the one with the smallest worst error). Clips of one
// frame (no duration) cost nothing to choose.
BudgetChoice chooseByBudget(const Character &c, const std::vector<const AnimationClip *> &clips,
                            const BudgetSearch &search);

// The fewest texel bytes of any texture chooseByBudget could choose: each clip at the lowest
// rate it tries, at the smallest precision tried, rows unpadded. Joint tracks that meet the
// budget in no more bytes are stored whatever the search finds, so it need not run.
uint64_t fewestTextureBytes(const Character &c, const std::vector<const AnimationClip *> &clips,
                            const BudgetSearch &search);

} // namespace crowd
