// ImageEncoder: runs' PNGs encoded by std::async workers, at most maxPending at a time.

#include "clipray/report/ImageEncoder.hpp"

#include <string>

#include "clipray/util/Check.hpp"

namespace clipray {

std::optional<ImagePolicy> parseImagePolicy(const std::string& text) {
  if (text == "none") return ImagePolicy::None;
  if (text == "failing") return ImagePolicy::Failing;
  if (text == "all") return ImagePolicy::All;
  return std::nullopt;
}

bool wantsImages(ImagePolicy policy, const RunMetrics& metrics) {
  return policy == ImagePolicy::All || (policy == ImagePolicy::Failing && !metrics.consistent());
}

bool wantsThumbnails(ImagePolicy policy) {
  return policy != ImagePolicy::None;
}

void ImageEncoder::submit(std::size_t key, const RunRecord& run, PixelComparison pixels,
                          bool fullImages) {
  while (!pending_.empty() && pending_.size() >= maxPending_) finishOldest();
  RunRecord header = run;
  header.images.clear();
  pending_.push_back({key, std::async(std::launch::async, [header = std::move(header), fullImages,
                                                           pixels = std::move(pixels)]() mutable {
                        if (fullImages) encodeRunImages(header, pixels);
                        encodeThumbnails(header, pixels);
                        if (fullImages) encodeClusterCrops(header, pixels);
                        return std::move(header.images);
                      })});
}

void ImageEncoder::finishOldest() {
  Pending oldest = std::move(pending_.front());
  pending_.erase(pending_.begin());
  done_.emplace_back(oldest.key, oldest.images.get());
}

void ImageEncoder::collect(std::vector<RunRecord>& runs) {
  while (!pending_.empty()) finishOldest();
  for (auto& [key, images] : done_) {
    CLIPRAY_CHECK(key < runs.size(), "ImageEncoder::collect: run " + std::to_string(key) + " of " +
                                         std::to_string(runs.size()));
    runs[key].images = std::move(images);
  }
  done_.clear();
}

}  // namespace clipray
