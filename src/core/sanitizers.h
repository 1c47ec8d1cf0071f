// Whether this translation unit is built with AddressSanitizer (GCC's -fsanitize=address defines
// __SANITIZE_ADDRESS__; Clang answers __has_feature): WF_UNDER_ASAN is then 1.
#pragma once

#if defined(__SANITIZE_ADDRESS__)
#define WF_UNDER_ASAN 1
#elif defined(__has_feature)
#if __has_feature(address_sanitizer)
#define WF_UNDER_ASAN 1
#endif
#endif
