#include "text_tokens.hpp"

#include <algorithm>
#include <cctype>
#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <memory>

#include "fclib_error.hpp"

namespace frix::fclib {

namespace {

bool is_space(char c) { return std::isspace(static_cast<unsigned char>(c)) != 0; }

struct FileCloser {
    void operator()(std::FILE *f) const { std::fclose(f); }
};

}  // namespace

TextTokens::TextTokens(const char *path) : path_(path) {
    std::unique_ptr<std::FILE, FileCloser> file(std::fopen(path, "rb"));
    if (!file) raise(FRIX_ERR_IO, "cannot open '%s': %s", path, std::strerror(errno));
    char buffer[1 << 16];
    size_t got;
    while ((got = std::fread(buffer, 1, sizeof buffer, file.get())) > 0) text_.append(buffer, got);
    if (std::ferror(file.get())) raise(FRIX_ERR_IO, "cannot read '%s'", path);
    for (size_t i = 0; i < text_.size();) {
        while (i < text_.size() && is_space(text_[i])) ++i;
        if (i == text_.size()) break;
        offsets_.push_back(i);
        while (i < text_.size() && !is_space(text_[i])) ++i;
    }
}

std::string TextTokens::token(size_t index) const {
    size_t start = offsets_[index], end = start;
    while (end < text_.size() && !is_space(text_[end])) ++end;
    return text_.substr(start, end - start);
}

namespace {
// A token as quoted in a message: long garbage is cut.
std::string shown(const std::string &token) {
    return token.size() <= 40 ? token : token.substr(0, 40) + "...";
}
}  // namespace

int TextTokens::line_of(size_t index) const {
    const size_t at = index < offsets_.size() ? offsets_[index] : text_.size();
    return 1 + static_cast<int>(std::count(text_.begin(), text_.begin() + at, '\n'));
}

void TextTokens::error(const std::string &message) const {
    raise(FRIX_ERR_FORMAT, "'%s': line %d: %s", path(), line_of(next_), message.c_str());
}

void TextTokens::require(size_t n, const char *what) const {
    if (remaining() < n)
        error("the file ends early: " + std::string(what) + " needs " + std::to_string(n) +
              " more numbers, " + std::to_string(remaining()) + " left");
}

int64_t TextTokens::integer(const char *what, int64_t lo, int64_t hi) {
    if (remaining() == 0) error(std::string("the file ends where ") + what + " was expected");
    const std::string text = token(next_);
    char *end = nullptr;
    errno = 0;
    const long long value = std::strtoll(text.c_str(), &end, 10);
    if (end == text.c_str() || *end != '\0' || errno == ERANGE)
        error(std::string("expected an integer (") + what + "), found '" + shown(text) + "'");
    if (value < lo || value > hi)
        error(std::string(what) + " is " + text + ", outside [" + std::to_string(lo) + ", " +
              std::to_string(hi) + "]");
    ++next_;
    return value;
}

double TextTokens::real(const char *what) {
    if (remaining() == 0) error(std::string("the file ends where ") + what + " was expected");
    const std::string text = token(next_);
    char *end = nullptr;
    // strtod rounds correctly, as the fscanf("%lf") Siconos reads with: same bits.
    const double value = std::strtod(text.c_str(), &end);
    if (end == text.c_str() || *end != '\0')
        error(std::string("expected a number (") + what + "), found '" + shown(text) + "'");
    if (!std::isfinite(value))
        raise(FRIX_ERR_NOT_FINITE, "'%s': line %d: %s is '%s', not finite", path(),
              line_of(next_), what, shown(text).c_str());
    ++next_;
    return value;
}

}  // namespace frix::fclib
