// Which depth convention a near plane was built for (BuiltFor.hpp).

#include "clipray/check/BuiltFor.hpp"

#include <cmath>
#include <cstdio>
#include <optional>

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

// A stated near or far plane agrees with a reading within the reading's uncertainty (plus
// kStatedPlaneTolerance).
bool statedMatches(const Uncertain& reading, double stated) {
  return std::abs(reading.value - stated) <=
         reading.error + kStatedPlaneTolerance * std::abs(stated);
}

// The stated near plane settles the reading it matches, when it matches one only; nullopt when it
// matches both (the readings' rules decide) or neither.
std::optional<BuildReading> statedBuild(const Uncertain& no, const Uncertain& zo, double stated) {
  const bool byNo = statedMatches(no, stated), byZo = statedMatches(zo, stated);
  if (byNo == byZo) return std::nullopt;
  return BuildReading{byNo ? "no" : "zo", "the stated near plane, " + number(stated), true};
}

// Why an orthographic reading is a value an app sets (readOrthographicBuild); empty when it is
// none, or when its uncertainty is too wide to tell (then undecided is set).
std::string orthographicExplanation(const Uncertain& near, const Uncertain& far, bool& undecided) {
  if (std::abs(near.value + far.value) <= near.error + far.error &&
      std::abs(far.value) > far.error) {
    return "-far, a volume centred on the camera";
  }
  switch (roundness(near)) {
    case Roundness::Round:
      return std::abs(near.value) <= near.error + 4.0 * std::ldexp(1.0, -53) * std::abs(near.value)
                 ? std::string("0, a volume starting at the camera")
                 : "within its uncertainty of the round number " +
                       number(nearestRoundNumber(near.value));
    case Roundness::Undecided:
      undecided = true;
      return "";
    case Roundness::NotRound:
      return "";
  }
  return "";
}

}  // namespace

BuildReading readOrthographicBuild(const Uncertain& no, const Uncertain& zo, const Uncertain& far,
                                   std::optional<double> stated) {
  if (stated) {
    if (std::optional<BuildReading> settled = statedBuild(no, zo, *stated)) return *settled;
  }
  BuildReading reading;
  if (stated && !statedMatches(no, *stated)) reading.statedMatches = false;
  const std::string both = " (" + shownReading(no) + " if NO, " + shownReading(zo) + " if ZO)";
  bool undecided = false;
  const std::string whyNo = orthographicExplanation(no, far, undecided);
  const std::string whyZo = orthographicExplanation(zo, far, undecided);
  if (!whyNo.empty() && !whyZo.empty()) {
    reading.builtFor = "ambiguous";
    reading.reason = "under NO the near plane reads " + shownReading(no) + " (" + whyNo +
                     "), under ZO " + shownReading(zo) + " (" + whyZo +
                     "): an app sets either, and the matrix is that one volume under both; "
                     "--near settles it";
  } else if (undecided) {
    reading.builtFor = "ambiguous";
    reading.reason =
        "a reading of the near plane lies within its uncertainty of a round number, but an "
        "uncertainty that wide (over 1/100 of the spacing of two-digit numbers there) is met by "
        "chance" +
        both + "; --near settles it";
  } else if (whyNo.empty() && whyZo.empty()) {
    reading.builtFor = "ambiguous";
    reading.reason =
        "neither reading of the near plane is a round number or -far (a volume centred on the "
        "camera)" +
        both + "; --near settles it";
  } else {
    const bool byNo = !whyNo.empty();
    const Uncertain& other = byNo ? zo : no;
    reading.builtFor = byNo ? "no" : "zo";
    reading.reason = std::string("the ") + (byNo ? "NO" : "ZO") + " reading " +
                     withError(byNo ? no : zo) + " is " + (byNo ? whyNo : whyZo) + "; the " +
                     (byNo ? "ZO" : "NO") + " reading " + withError(other) + " lies " +
                     number(std::abs(other.value - nearestRoundNumber(other.value))) +
                     " from the nearest round number, " + number(nearestRoundNumber(other.value)) +
                     ", and is not -far";
  }
  return reading;
}

BuildReading readBuild(const std::optional<Uncertain>& no, const std::optional<Uncertain>& zo,
                       std::optional<double> stated, const std::string& what) {
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
    if (std::optional<BuildReading> settled = statedBuild(*no, *zo, *stated)) return *settled;
    if (!statedMatches(*no, *stated)) {
      BuildReading fallback = readBuild(no, zo, std::nullopt, what);
      fallback.statedMatches = false;
      return fallback;
    }
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
