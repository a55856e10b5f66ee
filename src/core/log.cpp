// log.cpp: one stderr logger shared by all commands. Warnings print even with --quiet.
#include "ltm/core/log.h"

#include <atomic>

#include <spdlog/sinks/stdout_sinks.h>
#include <spdlog/spdlog.h>

namespace ltm {
namespace {
std::atomic<LogLevel> g_level{LogLevel::normal};

spdlog::logger &logger() {
    static std::shared_ptr<spdlog::logger> l = [] {
        auto lg = std::make_shared<spdlog::logger>(
            "ltm", std::make_shared<spdlog::sinks::stderr_sink_mt>());
        lg->set_pattern("%^[%l]%$ %v");
        lg->set_level(spdlog::level::trace);
        return lg;
    }();
    return *l;
}
}  // namespace

void set_log_level(LogLevel level) { g_level = level; }
LogLevel log_level() { return g_level; }

void log_message_info(const std::string &msg) { logger().info(msg); }
void log_message_warn(const std::string &msg) { logger().warn(msg); }
void log_message_debug(const std::string &msg) { logger().debug(msg); }

}  // namespace ltm
