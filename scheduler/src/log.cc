#include "tessera/scheduler/log.h"

#include <unistd.h>

#include <array>
#include <atomic>
#include <cerrno>
#include <cstdlib>
#include <memory>
#include <mutex>
#include <string>

#include "absl/strings/ascii.h"
#include "absl/strings/str_cat.h"

// The level names TESSERA_LOG_LEVEL takes ("warn", where spdlog says "warning"). spdlog is
// header-only here, compiled into this file alone, so the names are this library's own.
#define SPDLOG_LEVEL_NAMES \
  { "trace", "debug", "info", "warn", "error", "critical", "off" }
#include <spdlog/details/log_msg.h>
#include <spdlog/logger.h>
#include <spdlog/pattern_formatter.h>
#include <spdlog/sinks/base_sink.h>

namespace tessera::log {
namespace {

constexpr const char* kPattern = "[%Y-%m-%d %H:%M:%S.%e] [%n] [%l] %v";
constexpr std::array<const char*, 5> kComponentNames = {"api", "scheduler", "worker", "render",
                                                        "grpc"};

// Set while this thread runs the application's callback: what it logs goes to stderr, as the
// callback's sink is busy (with this very thread).
thread_local bool t_in_callback = false;

void WriteAll(const char* data, size_t size) {
  while (size > 0) {
    const ssize_t n = ::write(STDERR_FILENO, data, size);
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) return;  // nowhere to say it
    data += n;
    size -= static_cast<size_t>(n);
  }
}

// Every logger's one sink: the application's callback when it installed one, else stderr, a line
// in one write(2) (a pipe shared with other processes gets whole lines).
class Sink final : public spdlog::sinks::base_sink<std::mutex> {
 public:
  Sink() { set_pattern(kPattern); }

  void SetCallback(Callback callback, void* user) {
    {
      std::lock_guard<std::mutex> lock(callback_mu_);
      callback_ = callback;
      user_ = user;
    }
    // Waits for a line being handed to the old callback (base_sink::flush takes the sink's
    // mutex): afterwards the application may free what `user` points at.
    if (!t_in_callback) flush();
  }

  // Formats as on stderr, without the sink (for lines logged from inside the callback).
  std::string Format(const spdlog::details::log_msg& msg) {
    std::lock_guard<std::mutex> lock(format_mu_);
    spdlog::memory_buf_t formatted;
    fallback_formatter_.format(msg, formatted);
    return std::string(formatted.data(), formatted.size());
  }

 protected:
  void sink_it_(const spdlog::details::log_msg& msg) override {
    Callback callback;
    void* user;
    {
      std::lock_guard<std::mutex> lock(callback_mu_);
      callback = callback_;
      user = user_;
    }
    if (callback != nullptr) {
      const std::string text(msg.payload.data(), msg.payload.size());
      t_in_callback = true;
      callback(static_cast<int>(msg.level), text.c_str(), user);
      t_in_callback = false;
      return;
    }
    spdlog::memory_buf_t formatted;
    formatter_->format(msg, formatted);
    WriteAll(formatted.data(), formatted.size());
  }
  void flush_() override {}

 private:
  std::mutex callback_mu_;
  Callback callback_ = nullptr;
  void* user_ = nullptr;
  std::mutex format_mu_;
  spdlog::pattern_formatter fallback_formatter_{kPattern};
};

struct Loggers {
  std::shared_ptr<Sink> sink = std::make_shared<Sink>();
  std::array<std::unique_ptr<spdlog::logger>, kComponentNames.size()> by_component;
  Loggers() {
    for (size_t i = 0; i < kComponentNames.size(); ++i) {
      by_component[i] = std::make_unique<spdlog::logger>(kComponentNames[i], sink);
      by_component[i]->set_level(spdlog::level::trace);  // Enabled() filters
      by_component[i]->flush_on(spdlog::level::off);     // each line is written whole at once
    }
  }
};

// Never destroyed: threads may log while the process exits.
Loggers& TheLoggers() {
  static Loggers* loggers = new Loggers;
  return *loggers;
}

constexpr int kUnset = -1;
std::atomic<int> g_level{kUnset};

int LevelFromEnvironment() {
  const char* env = std::getenv("TESSERA_LOG_LEVEL");
  if (env == nullptr || *env == '\0') return static_cast<int>(Level::kInfo);
  absl::StatusOr<Level> level = ParseLevel(env);
  if (level.ok()) return static_cast<int>(*level);
  // Said once, by the thread that read it first, once the level is known.
  static std::once_flag said;
  std::call_once(said, [&] {
    g_level.store(static_cast<int>(Level::kInfo));
    Write(Component::kScheduler, Level::kWarn,
          absl::StrCat("TESSERA_LOG_LEVEL ignored: ", level.status().message(), "; using info"));
  });
  return static_cast<int>(Level::kInfo);
}

spdlog::logger& LoggerOf(Component component) {
  const size_t i = static_cast<size_t>(component);
  return *TheLoggers().by_component[i < kComponentNames.size() ? i : 0];
}

}  // namespace

Level CurrentLevel() {
  int level = g_level.load(std::memory_order_relaxed);
  if (level == kUnset) {
    int expected = kUnset;
    const int from_env = LevelFromEnvironment();
    g_level.compare_exchange_strong(expected, from_env);
    level = g_level.load();
  }
  return static_cast<Level>(level);
}

void SetLevel(Level level) { g_level.store(static_cast<int>(level)); }

absl::StatusOr<Level> ParseLevel(absl::string_view text) {
  const std::string name = absl::AsciiStrToLower(absl::StripAsciiWhitespace(text));
  if (name == "trace") return Level::kTrace;
  if (name == "debug") return Level::kDebug;
  if (name == "info") return Level::kInfo;
  if (name == "warn" || name == "warning") return Level::kWarn;
  if (name == "error") return Level::kError;
  if (name == "off") return Level::kOff;
  return absl::InvalidArgumentError(
      absl::StrCat("'", text, "' is not a log level (trace, debug, info, warn, error or off)"));
}

const char* LevelName(Level level) {
  switch (level) {
    case Level::kTrace:
      return "trace";
    case Level::kDebug:
      return "debug";
    case Level::kInfo:
      return "info";
    case Level::kWarn:
      return "warn";
    case Level::kError:
      return "error";
    case Level::kOff:
      return "off";
  }
  return "?";
}

bool Enabled(Level level) {
  return level != Level::kOff && static_cast<int>(level) >= static_cast<int>(CurrentLevel());
}

void Write(Component component, Level level, absl::string_view message) {
  if (!Enabled(level)) return;
  if (!message.empty() && message.back() == '\n') message.remove_suffix(1);
  spdlog::logger& logger = LoggerOf(component);
  const auto spd_level = static_cast<spdlog::level::level_enum>(level);
  const spdlog::string_view_t text(message.data(), message.size());
  if (t_in_callback) {
    const spdlog::details::log_msg msg(logger.name(), spd_level, text);
    const std::string line = TheLoggers().sink->Format(msg);
    WriteAll(line.data(), line.size());
    return;
  }
  logger.log(spdlog::source_loc{}, spd_level, text);
}

void SetCallback(Callback callback, void* user) { TheLoggers().sink->SetCallback(callback, user); }

bool ParseLine(absl::string_view line, Level* level, absl::string_view* message) {
  // "[date time] [component] [level] message"
  auto bracket = [&line](absl::string_view* inside) {
    if (line.size() < 2 || line.front() != '[') return false;
    const size_t close = line.find(']');
    if (close == absl::string_view::npos) return false;
    *inside = line.substr(1, close - 1);
    line.remove_prefix(close + 1);
    if (!line.empty() && line.front() == ' ') line.remove_prefix(1);
    return true;
  };
  absl::string_view time, component, name;
  if (!bracket(&time) || !bracket(&component) || !bracket(&name)) return false;
  if (time.size() < 19 || time[4] != '-' || time[10] != ' ') return false;
  absl::StatusOr<Level> parsed = ParseLevel(name);
  if (!parsed.ok() && name != "critical") return false;
  *level = parsed.ok() ? *parsed : Level::kError;
  *message = line;
  return true;
}

}  // namespace tessera::log
