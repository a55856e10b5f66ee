# ltm_warnings: warning flags as an INTERFACE target, never global CMAKE_CXX_FLAGS.
add_library(ltm_warnings INTERFACE)
target_compile_options(ltm_warnings INTERFACE
  $<$<CXX_COMPILER_ID:GNU,Clang>:-Wall -Wextra -Wshadow -Wnon-virtual-dtor -Wpedantic
                                 -Wno-missing-field-initializers>)
