// The whitespace-separated numbers of a text file, read one after the other with the
// file's line numbers kept for messages. Used by the Siconos .dat reader, whose format is a
// plain sequence of numbers in which line breaks carry no meaning.
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

namespace frix::fclib {

class TextTokens {
   public:
    // Reads the whole file (FRIX_ERR_IO if it cannot be read).
    explicit TextTokens(const char *path);

    const char *path() const { return path_.c_str(); }
    size_t remaining() const { return offsets_.size() - next_; }

    // The next token as an integer in [lo, hi] or as a finite double; FRIX_ERR_FORMAT with
    // the line and `what` when the file ends or the token is not such a number.
    int64_t integer(const char *what, int64_t lo, int64_t hi);
    double real(const char *what);

    // Fails unless at least n tokens are left: checked before sizing anything from the
    // file, so that a corrupt size is a message rather than a huge allocation.
    void require(size_t n, const char *what) const;

    // Raises FRIX_ERR_FORMAT "'path': line L: <message>" about the next token.
    [[noreturn]] void error(const std::string &message) const;

   private:
    int line_of(size_t token) const;
    std::string token(size_t index) const;

    std::string path_;
    std::string text_;
    std::vector<size_t> offsets_;  // start of each token in text_
    size_t next_ = 0;
};

}  // namespace frix::fclib
