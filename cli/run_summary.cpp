#include "cli/run_summary.h"

#include <unistd.h>

#include <algorithm>
#include <cmath>

namespace invmap::cli {

void RunSummary::Add(const Results& results, std::size_t count) {
  for (std::size_t i = 0; i < count; ++i) {
    ++points_;
    switch (results.status[i]) {
      case Status::Found: {
        const double d = results.distance[i];
        minDistance_ = found_ ? std::min(minDistance_, d) : d;
        maxDistance_ = found_ ? std::max(maxDistance_, d) : d;
        sumDistance_ += d;
        ++found_;
        if (foundSeen_++ % stride_ == 0) samples_.push_back(static_cast<float>(d));
        if (samples_.size() >= kMaxSamples) {
          // Keep every other sample and halve the sampling rate.
          for (std::size_t k = 0; 2 * k < samples_.size(); ++k) samples_[k] = samples_[2 * k];
          samples_.resize((samples_.size() + 1) / 2);
          stride_ *= 2;
        }
        break;
      }
      case Status::None:
        ++none_;
        break;
      case Status::Invalid:
        ++invalid_;
        break;
    }
  }
}

void RunSummary::Print(std::FILE* out, double seconds, double setupSeconds) const {
  std::fprintf(out, "points      %lld (found %lld, none %lld, invalid %lld)\n", static_cast<long long>(points_),
               static_cast<long long>(found_), static_cast<long long>(none_), static_cast<long long>(invalid_));
  const double pointSeconds = seconds - setupSeconds;
  std::fprintf(out, "time        %.3f s (geometry read and built in %.3f s), %.0f points/s\n", seconds, setupSeconds,
               pointSeconds > 0 ? points_ / pointSeconds : 0.0);
  if (found_ == 0) return;
  std::vector<float> sorted = samples_;
  std::sort(sorted.begin(), sorted.end());
  auto percentile = [&](double q) {
    const std::size_t k = static_cast<std::size_t>(std::floor(q * (sorted.size() - 1) + 0.5));
    return static_cast<double>(sorted[k]);
  };
  std::fprintf(out, "distance    min %.6g  mean %.6g  max %.6g\n", minDistance_, sumDistance_ / found_, maxDistance_);
  std::fprintf(out, "percentiles p50 %.6g  p90 %.6g  p99 %.6g  p99.9 %.6g\n", percentile(0.5), percentile(0.9),
               percentile(0.99), percentile(0.999));
}

Progress::Progress(bool quiet, std::int64_t total)
    : enabled_(!quiet && isatty(STDERR_FILENO)), total_(total), start_(std::chrono::steady_clock::now()) {}

void Progress::Update(std::int64_t done) {
  if (!enabled_) return;
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count();
  const double rate = seconds > 0 ? done / seconds : 0.0;
  if (total_ > 0) {
    const double fraction = std::min(1.0, static_cast<double>(done) / total_);
    const int width = 30, filled = static_cast<int>(fraction * width);
    const double left = rate > 0 ? (total_ - done) / rate : 0.0;
    std::fprintf(stderr, "\r[%.*s%*s] %3.0f%% %lld/%lld points, %.0f points/s, %.0f s left ", filled,
                 "##############################", width - filled, "", 100 * fraction, static_cast<long long>(done),
                 static_cast<long long>(total_), rate, left);
  } else {
    std::fprintf(stderr, "\r%lld points, %.0f points/s ", static_cast<long long>(done), rate);
  }
  std::fflush(stderr);
}

void Progress::Done() {
  if (enabled_) std::fprintf(stderr, "\r\033[K");
}

}  // namespace invmap::cli
