// How queries/ includes CGAL 5.5 so that the same code builds for the host
// and for the robot (arm-none-eabi, newlib, -fno-exceptions, soft float).
// cgal_kernel.h includes this before any CGAL header; nothing else should.
//
// Each item below answers one problem found building CGAL for the Teensy:
//
// 1. Standard streams. CGAL/config.h includes <iostream>, and with GCC 12
//    every translation unit that includes it constructs std::cout & co. at
//    start-up. That constructor drags about 270 KB of libstdc++ (locales,
//    stream buffers) into a firmware image, more than the Teensy's 256 KB of
//    flash. CGAL names the streams only in diagnostics the queries never
//    reach, so they are declared here and <iostream> itself is skipped.
// 2. Rounding modes. CGAL/FPU.h names FE_UPWARD & co., which newlib's
//    soft-float <fenv.h> does not define. They only serve interval
//    arithmetic (filtered kernels), which the exact Int128 kernel never runs.
// 3. Checks. CGAL's failure handlers throw, and core code has no
//    exceptions. CGAL's checks are compiled out (CGAL_NDEBUG) and, where
//    exceptions are off, its handler definitions (CGAL/assertions_impl.h)
//    are replaced by geometry.cpp's, which stop through SYROF_CHECK's path.
// 4. RTTI. CGAL/Object.h and CGAL/Handle_for_virtual.h use typeid in inline
//    functions the queries never call; queries/CMakeLists.txt compiles
//    the CGAL translation unit with -frtti on bare metal. No polymorphic
//    type is emitted, so no RTTI data reaches an image.
#pragma once

// 1. Standard streams: declared, not constructed.
#include <istream>
#include <ostream>
#ifndef _GLIBCXX_IOSTREAM
#define _GLIBCXX_IOSTREAM 1
namespace std {  // NOLINT: the declarations libstdc++'s <iostream> would make
extern istream cin;
extern ostream cout;
extern ostream cerr;
extern ostream clog;
}  // namespace std
#endif

// 2. Rounding-mode names for newlib's soft-float <fenv.h>.
#include <fenv.h>
#ifndef FE_UPWARD
#define FE_TONEAREST 0
#define FE_UPWARD 1
#define FE_DOWNWARD 2
#define FE_TOWARDZERO 3
#endif

// 3. Checks off; without exceptions, SyROF's failure handlers.
#ifndef CGAL_NDEBUG
#define CGAL_NDEBUG 1
#endif
#if !defined(__cpp_exceptions)
#define SYROF_QUERIES_CGAL_OWN_FAILURE_HANDLERS 1
// What CGAL/assertions_impl.h would include, without its throwing handlers.
// clang-format off
#include <CGAL/config.h>
#include <CGAL/assertions_behaviour.h>
#include <CGAL/exceptions.h>
// clang-format on
#define CGAL_ASSERTIONS_IMPL_H 1
#endif
