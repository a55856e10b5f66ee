// log.h: leveled logging to stderr (spdlog underneath). Arguments are streamed like LTM_THROW's.
#pragma once

#include <string>

#include "ltm/core/error.h"

namespace ltm {

enum class LogLevel { quiet = 0, normal = 1, verbose = 2 };

void set_log_level(LogLevel level);
LogLevel log_level();

void log_message_info(const std::string &msg);
void log_message_warn(const std::string &msg);
void log_message_debug(const std::string &msg);

template <typename... A> void log_info(const A &...a) {
    if (log_level() >= LogLevel::normal) log_message_info(detail::concat(a...));
}
template <typename... A> void log_warn(const A &...a) { log_message_warn(detail::concat(a...)); }
template <typename... A> void log_debug(const A &...a) {
    if (log_level() >= LogLevel::verbose) log_message_debug(detail::concat(a...));
}

}  // namespace ltm
