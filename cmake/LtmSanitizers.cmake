# ltm_sanitize: AddressSanitizer + UBSan when LTM_SANITIZE=ON, empty otherwise.
add_library(ltm_sanitize INTERFACE)
if(LTM_SANITIZE)
  target_compile_options(ltm_sanitize INTERFACE -fsanitize=address,undefined -fno-omit-frame-pointer)
  target_link_options(ltm_sanitize INTERFACE -fsanitize=address,undefined)
endif()
