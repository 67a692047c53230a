#pragma once
// Encodes runs' PNGs (the full-size images --images asks for, and every run's thumbnails) on
// worker threads while the caller goes on with the next run (clipray reconcile): deflating four
// 1080p images costs about what comparing them does, and nothing in the next run waits for it. At
// most maxPending runs wait to be encoded at once, each holding its per-pixel comparison (~25 B per
// pixel); submitting one more first waits for the oldest.

#include <cstddef>
#include <future>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "clipray/compare/Reconcile.hpp"
#include "clipray/report/Report.hpp"
#include "clipray/report/RunImages.hpp"

namespace clipray {

// Which runs get their images written (clipray reconcile --images).
enum class ImagePolicy {
  None,     // none
  Failing,  // the inconsistent runs'
  All,      // every run's
};
// "none", "failing", "all"; nullopt for anything else.
std::optional<ImagePolicy> parseImagePolicy(const std::string& text);
// Whether a run with these metrics gets its four full-size images (and its cluster crops) under
// the policy.
bool wantsImages(ImagePolicy policy, const RunMetrics& metrics);
// Whether runs get their thumbnails (index.html shows them): under any policy but None. They cost
// one pass over the frame and two PNGs of at most 160 x 160 pixels.
bool wantsThumbnails(ImagePolicy policy);

class ImageEncoder {
 public:
  explicit ImageEncoder(std::size_t maxPending = 2) : maxPending_(maxPending) {}
  // Encodes the run's thumbnails (encodeThumbnails) on a worker thread, and with fullImages its
  // four full-size images and cluster crops too (encodeRunImages, encodeClusterCrops); key names
  // the run for collect(). The record is copied (its fields name the images), the pixels are taken.
  void submit(std::size_t key, const RunRecord& run, PixelComparison pixels, bool fullImages);
  // Waits for every submitted run and moves each one's images into runs[key] (a key past the
  // end is an error). Rethrows the first encoding failure.
  void collect(std::vector<RunRecord>& runs);

 private:
  struct Pending {
    std::size_t key;
    std::future<std::vector<EncodedImage>> images;
  };
  void finishOldest();
  std::size_t maxPending_;
  std::vector<Pending> pending_;
  std::vector<std::pair<std::size_t, std::vector<EncodedImage>>> done_;
};

}  // namespace clipray
