// error.h: the three error tiers of ltm (see STYLE.md).
//  1. Bad input (files, configs, CLI): LTM_THROW(...) throws ltm::Error; only run_cli() catches.
//  2. Invariants: LTM_CHECK / LTM_CHECK_EQ, always on, print both operands.
//  3. Hot-loop invariants: LTM_DCHECK, debug builds only.
#pragma once

#include <sstream>
#include <stdexcept>
#include <string>

namespace ltm {

/// Error for bad input; its message is the whole one-line diagnostic ("file:line: what").
class Error : public std::runtime_error {
public:
    explicit Error(const std::string &what) : std::runtime_error(what) {}
};

/// The first line of an exception's message: what a user is shown (libtorch's messages go on
/// with a multi-line backtrace; nn/torch_runtime.h's exception_line drops that first).
inline std::string first_line(const std::string &msg) { return msg.substr(0, msg.find('\n')); }

namespace detail {
template <typename... Args> std::string concat(const Args &...args) {
    std::ostringstream os;
    (os << ... << args);
    return os.str();
}
[[noreturn]] void check_failed(const char *file, int line, const std::string &what);
}  // namespace detail

}  // namespace ltm

/// Throws ltm::Error with the streamed arguments, e.g. LTM_THROW(path, ":", line, ": bad key").
#define LTM_THROW(...) throw ::ltm::Error(::ltm::detail::concat(__VA_ARGS__))

#define LTM_CHECK(cond)                                                                    \
    do {                                                                                   \
        if (!(cond)) ::ltm::detail::check_failed(__FILE__, __LINE__, "CHECK(" #cond ")"); \
    } while (0)

#define LTM_CHECK_OP(a, op, b)                                                              \
    do {                                                                                    \
        const auto &ltm_a_ = (a);                                                           \
        const auto &ltm_b_ = (b);                                                           \
        if (!(ltm_a_ op ltm_b_))                                                            \
            ::ltm::detail::check_failed(                                                    \
                __FILE__, __LINE__,                                                         \
                ::ltm::detail::concat("CHECK(" #a " " #op " " #b ") with ", ltm_a_, " vs ", \
                                      ltm_b_));                                             \
    } while (0)

#define LTM_CHECK_EQ(a, b) LTM_CHECK_OP(a, ==, b)
#define LTM_CHECK_NE(a, b) LTM_CHECK_OP(a, !=, b)
#define LTM_CHECK_LT(a, b) LTM_CHECK_OP(a, <, b)
#define LTM_CHECK_LE(a, b) LTM_CHECK_OP(a, <=, b)
#define LTM_CHECK_GT(a, b) LTM_CHECK_OP(a, >, b)
#define LTM_CHECK_GE(a, b) LTM_CHECK_OP(a, >=, b)

#ifdef NDEBUG
#define LTM_DCHECK(cond) ((void)0)
#else
#define LTM_DCHECK(cond) LTM_CHECK(cond)
#endif
