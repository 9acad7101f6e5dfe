#include "ocg/core/logging.h"

#include <spdlog/sinks/stdout_color_sinks.h>
#include <spdlog/spdlog.h>
#include <unistd.h>

#include <cmath>
#include <cstdio>
#include <stdexcept>

namespace ocg {
namespace {

constexpr auto kRedrawInterval = std::chrono::milliseconds(100);

std::string FormatDuration(double seconds) {
  const long total = std::lround(seconds);
  char buffer[32];
  if (total >= 3600) {
    std::snprintf(buffer, sizeof(buffer), "%ldh%02ldm", total / 3600, (total % 3600) / 60);
  } else if (total >= 60) {
    std::snprintf(buffer, sizeof(buffer), "%ldm%02lds", total / 60, total % 60);
  } else {
    std::snprintf(buffer, sizeof(buffer), "%lds", total);
  }
  return buffer;
}

}  // namespace

void ConfigureLogging(const std::string& level) {
  const spdlog::level::level_enum parsed = spdlog::level::from_str(level);
  // from_str maps unknown names to "off"; only accept "off" when asked for.
  if (parsed == spdlog::level::off && level != "off") {
    throw std::invalid_argument("unknown log level '" + level +
                                "' (use trace, debug, info, warn, error or off)");
  }
  static const auto logger = [] {
    auto stderr_logger = spdlog::stderr_color_mt("ocg");
    stderr_logger->set_pattern("[%H:%M:%S.%e] [%^%l%$] %v");
    spdlog::set_default_logger(stderr_logger);
    return stderr_logger;
  }();
  logger->set_level(parsed);
}

ProgressLine::ProgressLine(std::string label, std::size_t total)
    : ProgressLine(std::move(label), total, ::isatty(::fileno(stdout)) != 0) {}

ProgressLine::ProgressLine(std::string label, std::size_t total, bool enabled)
    : label_(std::move(label)), total_(total), enabled_(enabled), start_(Clock::now()) {}

ProgressLine::~ProgressLine() { Finish(); }

std::string ProgressLine::Format(std::size_t done, double elapsed_seconds) const {
  const double rate = elapsed_seconds > 0 ? static_cast<double>(done) / elapsed_seconds : 0.0;
  char buffer[160];
  if (total_ > 0) {
    const double percent = 100.0 * static_cast<double>(done) / static_cast<double>(total_);
    const std::string eta =
        rate > 0 ? FormatDuration(static_cast<double>(total_ - std::min(done, total_)) / rate)
                 : "?";
    std::snprintf(buffer, sizeof(buffer), "%s %zu/%zu (%.1f%%)  %.1f fps  ETA %s", label_.c_str(),
                  done, total_, percent, rate, eta.c_str());
  } else {
    std::snprintf(buffer, sizeof(buffer), "%s %zu  %.1f fps", label_.c_str(), done, rate);
  }
  return buffer;
}

void ProgressLine::Update(std::size_t done) { Update(done, {}); }

void ProgressLine::Update(std::size_t done, const std::function<std::string()>& detail) {
  if (!enabled_) return;
  const Clock::time_point now = Clock::now();
  if (drawn_ && done != total_ && now - last_draw_ < kRedrawInterval) return;
  last_draw_ = now;
  drawn_ = true;
  const double elapsed = std::chrono::duration<double>(now - start_).count();
  std::string line = Format(done, elapsed);
  if (detail) line += "  " + detail();
  std::fprintf(stdout, "\r\033[K%s", line.c_str());
  std::fflush(stdout);
}

void ProgressLine::Finish() {
  if (enabled_ && drawn_) {
    std::fputc('\n', stdout);
    std::fflush(stdout);
  }
  drawn_ = false;
}

}  // namespace ocg
