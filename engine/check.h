#pragma once
// Always-on invariant checks for programmer errors (error kind 1 of the design: ../shared/design.md, "Errors").
// A failed check prints the condition with file and line, then aborts. Bad *input* never
// reaches these: it is rejected at load time with an InputError (see input_error.h).

#include <cstdio>
#include <cstdlib>

#define PWSIM_DEMAND(condition)                                                          \
  do {                                                                                   \
    if (!(condition)) {                                                                  \
      std::fprintf(stderr, "pwsim: invariant failed: %s (%s:%d)\n", #condition, __FILE__, \
                   __LINE__);                                                            \
      std::abort();                                                                      \
    }                                                                                    \
  } while (false)
