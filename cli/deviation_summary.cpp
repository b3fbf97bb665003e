#include "cli/deviation_summary.h"

#include <algorithm>
#include <cmath>

namespace invmap::cli {

void DeviationSummary::Add(const double* signedDistances, std::size_t count) {
  for (std::size_t i = 0; i < count; ++i) {
    const double d = signedDistances[i];
    if (std::isnan(d)) continue;
    ++count_;
    min_ = std::min(min_, d);
    max_ = std::max(max_, d);
    sum_ += d;
    sum2_ += d * d;
    inside_ += d < 0.0 ? 1 : 0;
    outside_ += d > 0.0 ? 1 : 0;
    within_ += std::abs(d) <= tolerance_ ? 1 : 0;
    below_ += d < -tolerance_ ? 1 : 0;
    if (seen_++ % stride_ == 0) samples_.push_back(static_cast<float>(d));
    if (samples_.size() >= kMaxSamples) {
      for (std::size_t k = 0; 2 * k < samples_.size(); ++k) samples_[k] = samples_[2 * k];
      samples_.resize((samples_.size() + 1) / 2);
      stride_ *= 2;
    }
  }
}

void DeviationSummary::Print(std::FILE* out) const {
  if (count_ == 0) return;
  const double mean = sum_ / count_;
  const double rms = std::sqrt(sum2_ / count_);
  const double sigma = std::sqrt(std::max(0.0, sum2_ / count_ - mean * mean));
  std::vector<float> sorted = samples_;
  std::sort(sorted.begin(), sorted.end());
  auto percentile = [&](double q) {
    return static_cast<double>(sorted[static_cast<std::size_t>(std::floor(q * (sorted.size() - 1) + 0.5))]);
  };
  std::fprintf(out, "deviation   (signed: + outside the part, - inside)\n");
  std::fprintf(out, "  mean %.6g  sigma %.6g  rms %.6g  min %.6g  max %.6g\n", mean, sigma, rms, min_, max_);
  std::fprintf(out, "  p0.1 %.6g  p1 %.6g  p50 %.6g  p99 %.6g  p99.9 %.6g\n", percentile(0.001), percentile(0.01),
               percentile(0.5), percentile(0.99), percentile(0.999));
  std::fprintf(out, "  outside %.2f %%  inside %.2f %%\n", 100.0 * outside_ / count_, 100.0 * inside_ / count_);
  if (std::isfinite(tolerance_)) {
    std::fprintf(out, "  within +-%.6g: %.2f %%  above: %.2f %%  below: %.2f %%\n", tolerance_, 100.0 * within_ / count_,
                 100.0 * (count_ - within_ - below_) / count_, 100.0 * below_ / count_);
  }
}

}  // namespace invmap::cli
