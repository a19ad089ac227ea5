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

#endif /* FRIX_EXPORT_H */
