// A small JSON writer for one-line machine-readable output. Strings are escaped (and
// invalid UTF-8 replaced by U+FFFD) and non-finite numbers are written as null, so the
// result is always valid JSON.
#pragma once

#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

namespace frix_cli {

class JsonWriter {
public:
    // `key` is nullptr for the top-level value and for array elements.
    void begin_object(const char *key = nullptr);
    void end_object();
    void begin_array(const char *key = nullptr);
    void end_array();

    void string(const char *key, std::string_view value);
    void number(const char *key, double value);
    void integer(const char *key, std::int64_t value);
    void boolean(const char *key, bool value);
    void null(const char *key);

    const std::string &text() const { return out_; }

private:
    void prefix(const char *key);

    std::string out_;
    std::vector<bool> first_;  // one entry per open object/array: no member written yet
};

std::string json_quote(std::string_view s);
// Shortest text that reads back to the same double; "null" if not finite.
std::string json_number(double v);

}  // namespace frix_cli
