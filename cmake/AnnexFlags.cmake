# Project-wide warning and sanitizer flags, carried by an interface target that each
# of our targets links privately (third-party targets stay untouched).
add_library(annex_flags INTERFACE)
add_library(annex::flags ALIAS annex_flags)
target_compile_options(annex_flags INTERFACE -Wall -Wextra)

# ANNEX_SANITIZE=thread: ThreadSanitizer (trackers on a pool, PNGs on a second thread);
# any other true value: AddressSanitizer + UndefinedBehaviorSanitizer.
if(ANNEX_SANITIZE STREQUAL "thread")
  target_compile_options(annex_flags INTERFACE -fsanitize=thread -fno-omit-frame-pointer)
  target_link_options(annex_flags INTERFACE -fsanitize=thread)
elseif(ANNEX_SANITIZE)
  target_compile_options(annex_flags INTERFACE
    -fsanitize=address,undefined -fno-omit-frame-pointer -fno-sanitize-recover=undefined)
  target_link_options(annex_flags INTERFACE -fsanitize=address,undefined)
endif()

# libFuzzer exists only in clang.
set(ANNEX_CAN_FUZZ OFF)
# (Not under ThreadSanitizer: the fuzz targets carry AddressSanitizer.)
if(ANNEX_FUZZ AND CMAKE_CXX_COMPILER_ID MATCHES "Clang" AND NOT ANNEX_SANITIZE STREQUAL "thread")
  set(ANNEX_CAN_FUZZ ON)
endif()
