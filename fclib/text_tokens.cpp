#include "text_tokens.hpp"

#include <cctype>
#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>

#include "fclib_error.hpp"

namespace frix::fclib {

namespace {

bool is_space(int c) { return std::isspace(c) != 0; }

// A token as quoted in a message: long garbage is cut, control characters escaped.
std::string shown(const std::string &token) {
    return printable(token.size() <= 40 ? token : token.substr(0, 40) + "...");
}

}  // namespace

int TextTokens::Scanner::get() {
    if (at_ == filled_) {
        filled_ = std::fread(block_.data(), 1, block_.size(), file_);
        at_ = 0;
        if (filled_ == 0) {
            if (std::ferror(file_)) raise(FRIX_ERR_IO, "cannot read '%s': %s", path_, std::strerror(errno));
            return -1;
        }
    }
    const int c = static_cast<unsigned char>(block_[at_++]);
    // A NUL is no character of a text file: the file is binary, or damaged.
    if (c == 0)
        raise(FRIX_ERR_FORMAT, "'%s': line %d: a NUL byte at byte offset %llu; a text problem file has none",
              path_, line_, static_cast<unsigned long long>(offset_));
    ++offset_;
    return c;
}

bool TextTokens::Scanner::next(std::string &token, int &line) {
    int c = get();
    while (c >= 0 && is_space(c)) {
        if (c == '\n') ++line_;
        c = get();
    }
    if (c < 0) return false;
    token.clear();
    line = line_;
    const uint64_t start = offset_ - 1;
    while (c >= 0 && !is_space(c)) {
        if (token.size() == kMaxTokenLength)
            raise(FRIX_ERR_FORMAT,
                  "'%s': line %d: the token at byte offset %llu is longer than %zu characters",
                  path_, line_, static_cast<unsigned long long>(start), kMaxTokenLength);
        token += static_cast<char>(c);
        c = get();
    }
    if (c == '\n') ++line_;
    return true;
}

TextTokens::TextTokens(const char *path)
    : path_(path), input_(open_regular_file(path)), scanner_(input_.file.get(), path_.c_str()) {
    {
        Scanner counter(input_.file.get(), path_.c_str());
        std::string token;
        int line = 0;
        while (counter.next(token, line)) ++total_;
    }
    if (std::fseek(input_.file.get(), 0, SEEK_SET) != 0)
        raise(FRIX_ERR_IO, "cannot read '%s': %s", path, std::strerror(errno));
    advance();
}

void TextTokens::advance() {
    const bool more = scanner_.next(next_, next_line_);
    if (!more) {
        next_line_ = scanner_.line();
        if (consumed_ < total_)
            raise(FRIX_ERR_IO, "cannot read '%s': the file changed while being read", path());
    }
}

void TextTokens::error(const std::string &message) const {
    raise(FRIX_ERR_FORMAT, "'%s': line %d: %s", path(), next_line_, message.c_str());
}

void TextTokens::require(size_t n, const char *what) const {
    if (remaining() < n)
        error("the file ends early: " + std::string(what) + " needs " + std::to_string(n) +
              " more numbers, " + std::to_string(remaining()) + " left");
}

int64_t TextTokens::integer(const char *what, int64_t lo, int64_t hi) {
    if (remaining() == 0) error(std::string("the file ends where ") + what + " was expected");
    const std::string &text = next_;
    char *end = nullptr;
    errno = 0;
    const long long value = std::strtoll(text.c_str(), &end, 10);
    if (end == text.c_str() || *end != '\0' || errno == ERANGE)
        error(std::string("expected an integer (") + what + "), found '" + shown(text) + "'");
    if (value < lo || value > hi)
        error(std::string(what) + " is " + shown(text) + ", outside [" + std::to_string(lo) + ", " +
              std::to_string(hi) + "]");
    ++consumed_;
    advance();
    return value;
}

double TextTokens::real(const char *what) {
    if (remaining() == 0) error(std::string("the file ends where ") + what + " was expected");
    const std::string &text = next_;
    char *end = nullptr;
    // strtod rounds correctly, as the fscanf("%lf") Siconos reads with: same bits.
    const double value = std::strtod(text.c_str(), &end);
    if (end == text.c_str() || *end != '\0')
        error(std::string("expected a number (") + what + "), found '" + shown(text) + "'");
    if (!std::isfinite(value))
        raise(FRIX_ERR_NOT_FINITE, "'%s': line %d: %s is '%s', not finite", path(), next_line_,
              what, shown(text).c_str());
    ++consumed_;
    advance();
    return value;
}

}  // namespace frix::fclib
