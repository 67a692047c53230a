// Which depth convention a near plane was built for (BuiltFor.hpp).

#include "clipray/check/BuiltFor.hpp"

#include <cmath>
#include <cstdio>

#include "clipray/check/CheckText.hpp"

namespace clipray::detail {

namespace {

std::string number(double value) {
  return checkNumber(value);
}

// A reading and its stated uncertainty, always shown: "0.1 +-2.9e-08".
std::string withError(const Uncertain& reading) {
  char error[32];
  std::snprintf(error, sizeof error, " +-%.2g", reading.error);
  return shownReading(reading) + error;
}

// Whether a reading is a value an app typed (at most two significant digits: 0.1, 0.05, 0.25,
// 1000): Round when such a number lies within its uncertainty (and double's own resolution), and
// the uncertainty is below 1/100 of the spacing of two-digit numbers there, so that a value typed
// at random lands that close to one by chance less than once in 50; NotRound when every round
// number lies further than its uncertainty; Undecided in between.
enum class Roundness { Round, NotRound, Undecided };

Roundness roundness(const Uncertain& reading) {
  const double v = reading.value;
  const double tolerance = reading.error + 4.0 * std::ldexp(1.0, -53) * std::abs(v);
  if (std::abs(v) <= tolerance) return Roundness::Round;  // 0 within its uncertainty
  const double round = nearestRoundNumber(v);
  if (std::abs(v - round) > tolerance) return Roundness::NotRound;
  // The spacing at the round number (0.01 at 0.1, 0.1 at 1), whichever side v reads from.
  const double spacing = std::pow(10.0, std::floor(std::log10(std::abs(round))) - 1.0);
  return tolerance <= spacing / 100.0 ? Roundness::Round : Roundness::Undecided;
}

}  // namespace

// behindCamera: readings are offsets from a camera position (orthographic), so a negative one puts
// the plane behind the camera, which an app rarely means when the other reading does not --
// except for a view volume centred on the camera (near = -far, with `far` the far plane's
// offset): gluOrtho2D and glOrtho(..., -1, 1) build exactly that, and its other reading (near 0)
// is just as natural, so it is left to the rules that follow.
BuildReading readBuild(const std::optional<Uncertain>& no, const std::optional<Uncertain>& zo,
                       std::optional<double> stated, const std::string& what, bool behindCamera,
                       const std::optional<Uncertain>& far) {
  // A reading lost to rounding (the eye far from the origin cancels the translation) is no
  // evidence for the other one: only a precise reading may stand alone.
  const auto precise = [](const std::optional<Uncertain>& r) {
    return r && r->error < 0.01 * std::abs(r->value);
  };
  if (!no && precise(zo)) return {"zo", "the NO reading puts the " + what + " behind the eye", {}};
  if (!zo && precise(no)) return {"no", "the ZO reading puts the " + what + " behind the eye", {}};
  if (!no || !zo) {
    return {"ambiguous",
            "the entries' precision cannot place the " + what +
                " (the camera's translation cancels it)",
            {}};
  }
  if (stated) {
    const auto matches = [&](const Uncertain& r) {
      return std::abs(r.value - *stated) <= r.error + kStatedPlaneTolerance * std::abs(*stated);
    };
    const bool byNo = matches(*no), byZo = matches(*zo);
    if (byNo != byZo) {
      return {byNo ? "no" : "zo", "the stated near plane, " + number(*stated), true};
    }
    if (!byNo) {
      BuildReading fallback = readBuild(no, zo, std::nullopt, what, behindCamera, far);
      fallback.statedMatches = false;
      return fallback;
    }
  }
  const auto centredOnCamera = [&](const Uncertain& near) {
    return far && std::abs(near.value + far->value) <= near.error + far->error;
  };
  if (behindCamera && (no->clearlyNegative() != zo->clearlyNegative()) &&
      !centredOnCamera(no->clearlyNegative() ? *no : *zo)) {
    const bool noBehind = no->clearlyNegative();
    return {noBehind ? "zo" : "no",
            std::string("the ") + (noBehind ? "NO" : "ZO") + " reading puts the " + what + " at " +
                shownReading(*(noBehind ? no : zo)) + ", behind the camera",
            {}};
  }
  const std::string both = " (" + shownReading(*no) + " if NO, " + shownReading(*zo) + " if ZO)";
  const Roundness roundNo = roundness(*no), roundZo = roundness(*zo);
  const auto decided = [](Roundness a, Roundness b) {
    return a == Roundness::Round && b == Roundness::NotRound;
  };
  if (decided(roundNo, roundZo) || decided(roundZo, roundNo)) {
    const bool byNo = roundNo == Roundness::Round;
    const Uncertain& round = byNo ? *no : *zo;
    const Uncertain& other = byNo ? *zo : *no;
    const std::string roundName = byNo ? "NO" : "ZO", otherName = byNo ? "ZO" : "NO";
    return {byNo ? "no" : "zo",
            "the " + roundName + " reading " + withError(round) +
                " lies within its uncertainty of the round number " +
                number(nearestRoundNumber(round.value)) + ", the " + otherName + " reading " +
                withError(other) + " lies " +
                number(std::abs(other.value - nearestRoundNumber(other.value))) +
                " from the nearest one, " + number(nearestRoundNumber(other.value)),
            {}};
  }
  if (roundNo == Roundness::Round && roundZo == Roundness::Round) {
    return {"ambiguous",
            "both readings of the " + what + " are round numbers within their uncertainty" + both,
            {}};
  }
  if (roundNo == Roundness::NotRound && roundZo == Roundness::NotRound) {
    return {"ambiguous",
            "neither reading of the " + what + " is a round number within its uncertainty" + both +
                "; --near settles it",
            {}};
  }
  return {"ambiguous",
          "a reading of the " + what +
              " lies within its uncertainty of a round number, but an uncertainty that wide (over "
              "1/100 of the spacing of two-digit numbers there) is met by chance" +
              both + "; --near settles it",
          {}};
}

}  // namespace clipray::detail
