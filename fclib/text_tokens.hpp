// The whitespace-separated numbers of a text file, read one after the other with the
// file's line numbers kept for messages. Used by the Siconos .dat reader, whose format is a
// plain sequence of numbers in which line breaks carry no meaning.
//
// The file is streamed, never loaded whole: a first pass counts its tokens (so that sizes
// read from the file can be checked against what follows before anything is sized from
// them) and refuses what no text problem holds, NUL bytes and tokens longer than
// kMaxTokenLength; the second pass reads the tokens. Only a block of the file and one token
// are held at a time.
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include "input_file.hpp"

namespace frix::fclib {

class TextTokens {
   public:
    // The longest number a file may write: 17 significant digits and an exponent need 25.
    static constexpr size_t kMaxTokenLength = 256;

    // Opens the file (FRIX_ERR_IO if it cannot be read or is not a regular file) and scans
    // it (FRIX_ERR_FORMAT at a NUL byte or an overlong token).
    explicit TextTokens(const char *path);

    const char *path() const { return path_.c_str(); }
    size_t remaining() const { return total_ - consumed_; }

    // The next token as an integer in [lo, hi] or as a finite double; FRIX_ERR_FORMAT with
    // the line and `what` when the file ends or the token is not such a number.
    int64_t integer(const char *what, int64_t lo, int64_t hi);
    double real(const char *what);

    // Fails unless at least n tokens are left: checked before sizing anything from the
    // file, so that a corrupt size is a message rather than a huge allocation (a token
    // takes at least 2 bytes of the file, so n numbers are at most 4 times its size).
    void require(size_t n, const char *what) const;

    // Raises FRIX_ERR_FORMAT "'path': line L: <message>" about the next token.
    [[noreturn]] void error(const std::string &message) const;

   private:
    // One pass over the file, a block at a time.
    class Scanner {
       public:
        Scanner(std::FILE *file, const char *path) : file_(file), path_(path), block_(1 << 16) {}
        // The next token and its line; false at the end of the file.
        bool next(std::string &token, int &line);
        int line() const { return line_; }

       private:
        // The next byte, or -1 at the end of the file.
        int get();

        std::FILE *file_;
        const char *path_;
        std::vector<char> block_;
        size_t at_ = 0, filled_ = 0;
        uint64_t offset_ = 0;  // of the next byte in the file
        int line_ = 1;
    };

    // Moves the lookahead to the token after it.
    void advance();

    std::string path_;
    InputFile input_;
    Scanner scanner_;
    size_t total_ = 0;     // tokens in the file
    size_t consumed_ = 0;  // tokens read
    std::string next_;     // the next token, when remaining() > 0
    int next_line_ = 1;    // its line, or the last line at the end
};

}  // namespace frix::fclib
