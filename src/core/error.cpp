// error.cpp: invariant failures. They are bugs, not bad input, so they say where in the code.
#include "ltm/core/error.h"

namespace ltm::detail {

void check_failed(const char *file, int line, const std::string &what) {
    throw std::logic_error(concat("internal error at ", file, ":", line, ": ", what));
}

}  // namespace ltm::detail
