// pbrt_tokenizer.h: tokens of the pbrt-v4 scene format (https://pbrt.org/fileformat-v4): bare
// words (directives, true/false), "quoted strings", numbers, [ and ]; '#' starts a comment.
// Every token knows its file:line:col, so parse errors can point at it.
#pragma once

#include <string>

namespace ltm {

struct PbrtToken {
    enum class Kind { word, string, number, open, close, end };
    Kind kind = Kind::end;
    std::string text;     ///< word or string contents (escapes resolved); number as written
    double number = 0.0;  ///< Kind::number
    std::string file;
    int line = 0, col = 0;
    /// "file:line:col" for error messages.
    std::string where() const;
};

class PbrtTokenizer {
public:
    /// `text` is the whole file; `file` names it in locations.
    PbrtTokenizer(std::string text, std::string file);
    /// The next token (Kind::end at the end, forever). Throws ltm::Error on an unterminated string
    /// or a character that starts no token.
    PbrtToken next();
    PbrtToken peek();

private:
    PbrtToken scan();
    std::string m_text, m_file;
    size_t m_pos = 0;
    int m_line = 1, m_col = 1;
    bool m_has_peek = false;
    PbrtToken m_peek;
};

}  // namespace ltm
