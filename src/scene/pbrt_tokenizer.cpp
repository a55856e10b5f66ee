// pbrt_tokenizer.cpp: a hand-written scanner (the format has no packaged parser).
#include "ltm/scene/pbrt_tokenizer.h"

#include <cctype>
#include <cerrno>
#include <cmath>
#include <cstdlib>

#include "ltm/core/error.h"

namespace ltm {

std::string PbrtToken::where() const { return detail::concat(file, ":", line, ":", col); }

PbrtTokenizer::PbrtTokenizer(std::string text, std::string file) : m_text(std::move(text)), m_file(std::move(file)) {}

PbrtToken PbrtTokenizer::peek() {
    if (!m_has_peek) {
        m_peek = scan();
        m_has_peek = true;
    }
    return m_peek;
}

PbrtToken PbrtTokenizer::next() {
    if (m_has_peek) {
        m_has_peek = false;
        return m_peek;
    }
    return scan();
}

PbrtToken PbrtTokenizer::scan() {
    auto advance = [&] {
        if (m_text[m_pos] == '\n') ++m_line, m_col = 1;
        else ++m_col;
        ++m_pos;
    };
    // Skip white space and comments.
    while (m_pos < m_text.size()) {
        const char c = m_text[m_pos];
        if (c == '#') {
            while (m_pos < m_text.size() && m_text[m_pos] != '\n') advance();
        } else if (std::isspace(static_cast<unsigned char>(c))) {
            advance();
        } else {
            break;
        }
    }
    PbrtToken t;
    t.file = m_file, t.line = m_line, t.col = m_col;
    if (m_pos >= m_text.size()) return t;
    const char c = m_text[m_pos];
    if (c == '[' || c == ']') {
        t.kind = c == '[' ? PbrtToken::Kind::open : PbrtToken::Kind::close;
        t.text = std::string(1, c);
        advance();
        return t;
    }
    if (c == '"') {
        t.kind = PbrtToken::Kind::string;
        advance();
        while (true) {
            if (m_pos >= m_text.size() || m_text[m_pos] == '\n') LTM_THROW(t.where(), ": unterminated string");
            const char d = m_text[m_pos];
            if (d == '"') {
                advance();
                break;
            }
            if (d == '\\') {
                advance();
                if (m_pos >= m_text.size()) LTM_THROW(t.where(), ": unterminated string");
                const char e = m_text[m_pos];
                t.text += e == 'n' ? '\n' : e == 't' ? '\t' : e;
                advance();
                continue;
            }
            t.text += d;
            advance();
        }
        return t;
    }
    if (std::isdigit(static_cast<unsigned char>(c)) || c == '-' || c == '+' || c == '.') {
        const size_t start = m_pos;
        while (m_pos < m_text.size()) {
            const char d = m_text[m_pos];
            if (!(std::isalnum(static_cast<unsigned char>(d)) || d == '.' || d == '-' || d == '+')) break;
            advance();
        }
        t.kind = PbrtToken::Kind::number;
        t.text = m_text.substr(start, m_pos - start);
        char *end = nullptr;
        errno = 0;
        t.number = std::strtod(t.text.c_str(), &end);
        if (end != t.text.c_str() + t.text.size() || errno == ERANGE || !std::isfinite(t.number))
            LTM_THROW(t.where(), ": '", t.text, "' is not a finite number");
        return t;
    }
    if (std::isalpha(static_cast<unsigned char>(c)) || c == '_') {
        const size_t start = m_pos;
        while (m_pos < m_text.size() &&
               (std::isalnum(static_cast<unsigned char>(m_text[m_pos])) || m_text[m_pos] == '_'))
            advance();
        t.kind = PbrtToken::Kind::word;
        t.text = m_text.substr(start, m_pos - start);
        return t;
    }
    LTM_THROW(t.where(), ": unexpected character '", std::string(1, c), "'");
}

}  // namespace ltm
