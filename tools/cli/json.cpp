#include "json.hpp"

#include <charconv>
#include <cmath>
#include <cstdio>

namespace frix_cli {

namespace {

// Length of the well-formed UTF-8 sequence starting at s[i], or 0 if it is not one.
std::size_t utf8_length(std::string_view s, std::size_t i) {
    auto byte = [&](std::size_t k) { return static_cast<unsigned char>(s[k]); };
    unsigned char c = byte(i);
    std::size_t len = c < 0x80 ? 1 : (c >> 5) == 0x6 ? 2 : (c >> 4) == 0xE ? 3 : (c >> 3) == 0x1E ? 4 : 0;
    if (len == 0 || i + len > s.size()) return 0;
    for (std::size_t k = 1; k < len; ++k)
        if ((byte(i + k) & 0xC0) != 0x80) return 0;
    if (len == 2 && c < 0xC2) return 0;  // overlong
    return len;
}

}  // namespace

std::string json_quote(std::string_view s) {
    std::string out = "\"";
    for (std::size_t i = 0; i < s.size();) {
        unsigned char c = static_cast<unsigned char>(s[i]);
        switch (c) {
            case '"': out += "\\\""; break;
            case '\\': out += "\\\\"; break;
            case '\n': out += "\\n"; break;
            case '\r': out += "\\r"; break;
            case '\t': out += "\\t"; break;
            case '\b': out += "\\b"; break;
            case '\f': out += "\\f"; break;
            default:
                if (c < 0x20 || c == 0x7F) {
                    char buf[8];
                    std::snprintf(buf, sizeof buf, "\\u%04x", static_cast<unsigned>(c));
                    out += buf;
                } else if (c >= 0x80) {
                    std::size_t len = utf8_length(s, i);
                    if (len == 0) {
                        out += "\\ufffd";
                        ++i;
                    } else {
                        out.append(s.substr(i, len));
                        i += len;
                    }
                    continue;
                } else {
                    out += static_cast<char>(c);
                }
        }
        ++i;
    }
    out += '"';
    return out;
}

std::string json_number(double v) {
    if (!std::isfinite(v)) return "null";
    char buf[32];
    auto res = std::to_chars(buf, buf + sizeof buf, v);
    return std::string(buf, res.ptr);
}

void JsonWriter::prefix(const char *key) {
    if (!first_.empty()) {
        if (!first_.back()) out_ += ',';
        first_.back() = false;
    }
    if (key) {
        out_ += json_quote(key);
        out_ += ':';
    }
}

void JsonWriter::begin_object(const char *key) {
    prefix(key);
    out_ += '{';
    first_.push_back(true);
}

void JsonWriter::end_object() {
    out_ += '}';
    first_.pop_back();
}

void JsonWriter::begin_array(const char *key) {
    prefix(key);
    out_ += '[';
    first_.push_back(true);
}

void JsonWriter::end_array() {
    out_ += ']';
    first_.pop_back();
}

void JsonWriter::string(const char *key, std::string_view value) {
    prefix(key);
    out_ += json_quote(value);
}

void JsonWriter::number(const char *key, double value) {
    prefix(key);
    out_ += json_number(value);
}

void JsonWriter::integer(const char *key, std::int64_t value) {
    prefix(key);
    out_ += std::to_string(value);
}

void JsonWriter::boolean(const char *key, bool value) {
    prefix(key);
    out_ += value ? "true" : "false";
}

void JsonWriter::null(const char *key) {
    prefix(key);
    out_ += "null";
}

}  // namespace frix_cli
