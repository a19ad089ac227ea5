/* frix — the one export macro of the public API.
 *
 * The library is built with hidden visibility; only declarations marked FRIX_API
 * are exported from libfrix.so. FRIX_BUILDING is defined while the library itself
 * is compiled. Static users need nothing special.
 */
#ifndef FRIX_EXPORT_H
#define FRIX_EXPORT_H

#if defined(_WIN32) || defined(__CYGWIN__)
#  if defined(FRIX_BUILDING)
#    define FRIX_API __declspec(dllexport)
#  elif defined(FRIX_SHARED)
#    define FRIX_API __declspec(dllimport)
#  else
#    define FRIX_API
#  endif
#elif defined(__GNUC__) && __GNUC__ >= 4
#  define FRIX_API __attribute__((visibility("default")))
#else
#  define FRIX_API
#endif

#if defined(__GNUC__) || defined(__clang__)
#  define FRIX_DEPRECATED(msg) __attribute__((deprecated(msg)))
#else
#  define FRIX_DEPRECATED(msg)
#endif

/* The public enums are int-sized in C. In C++ an enum without a fixed underlying type may
 * only hold values within the range of its enumerators, so a value a C caller passes (say an
 * unknown key, -1) would be undefined behaviour inside the library: give them int as base
 * (C++11 and later; the size is the same int for older C++ and for C). */
#if defined(__cplusplus) && __cplusplus >= 201103L
#  define FRIX_ENUM_BASE : int
#else
#  define FRIX_ENUM_BASE
#endif

#endif /* FRIX_EXPORT_H */
