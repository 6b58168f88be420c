// Lexer of word-address blocks (Fanuc, LinuxCNC, Sinumerik) shared by the reader and the
// syntax checker: block number, words (address letter + number text), comments, and the
// Sinumerik keyword statements (CYCLE85(...), SPOS=, SETMS(...), LIMS=, SCC[...], TRAORI,
// TRAFOOF, M2=70). Not public API.
#pragma once

#include <cctype>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "core/input_echo.h"

namespace tpcal::gcode::internal {

struct Word {
  char letter = 0;
  std::string value;  // as written ("140.", "-3.5", "43.4")
};

struct LexedBlock {
  std::string label;                  // "N120" or ""
  std::vector<Word> words;
  std::vector<std::string> keywords;  // Sinumerik statements, verbatim
  std::string comment;                // text of ( ... ) or after ';'
  bool comment_only = false;
  std::string error;                  // lexical error, "" if none
};

// `s` without leading and trailing white space.
inline std::string Trim(std::string_view s) {
  std::size_t a = 0, b = s.size();
  while (a < b && std::isspace(static_cast<unsigned char>(s[a]))) ++a;
  while (b > a && std::isspace(static_cast<unsigned char>(s[b - 1]))) --b;
  return std::string(s.substr(a, b - a));
}

// The lines of a program (LF or CRLF line ends; the CR is dropped), in order.
inline std::vector<std::string> Lines(std::string_view text) {
  std::vector<std::string> out;
  std::size_t pos = 0;
  while (pos < text.size()) {
    std::size_t eol = text.find('\n', pos);
    if (eol == std::string_view::npos) eol = text.size();
    std::string l(text.substr(pos, eol - pos));
    if (!l.empty() && l.back() == '\r') l.pop_back();
    out.push_back(std::move(l));
    pos = eol + 1;
  }
  return out;
}

inline bool IsNumberText(const std::string& s) {
  if (s.empty()) return false;
  std::size_t i = 0;
  if (s[0] == '+' || s[0] == '-') i = 1;
  bool digit = false, point = false;
  for (; i < s.size(); ++i) {
    if (std::isdigit(static_cast<unsigned char>(s[i]))) {
      digit = true;
    } else if (s[i] == '.' && !point) {
      point = true;
    } else {
      return false;
    }
  }
  return digit;
}

// `semicolon_comments`: ';' starts a comment to the end of the line (Sinumerik, LinuxCNC).
// `keywords`: recognise Sinumerik statements (then '(' belongs to a statement, not a comment).
inline LexedBlock LexBlock(std::string_view line, bool semicolon_comments, bool keywords) {
  LexedBlock b;
  std::string s(line);
  // Comments.
  std::string code;
  for (std::size_t i = 0; i < s.size(); ++i) {
    if (s[i] == '(' && !keywords) {
      const std::size_t close = s.find(')', i);
      if (close == std::string::npos) {
        b.error = "unclosed comment";
        return b;
      }
      const std::string text = s.substr(i + 1, close - i - 1);
      if (text.find('(') != std::string::npos) {
        b.error = "nested comment";
        return b;
      }
      b.comment += text;
      i = close;
    } else if (s[i] == ';' && semicolon_comments) {
      b.comment += s.substr(i + 1);
      break;
    } else {
      code += s[i];
    }
  }
  std::size_t i = 0;
  auto skip = [&]() {
    while (i < code.size() && std::isspace(static_cast<unsigned char>(code[i]))) ++i;
  };
  skip();
  if (i >= code.size()) {
    b.comment_only = true;
    return b;
  }
  while (i < code.size()) {
    skip();
    if (i >= code.size()) break;
    const char c = code[i];
    if (!std::isalpha(static_cast<unsigned char>(c))) {
      b.error = "unexpected character '" + EchoInput(std::string_view(&c, 1)) + "'";
      return b;
    }
    // Keyword: letters followed by more letters / '=' / '(' / '['.
    std::size_t j = i;
    while (j < code.size() && (std::isalnum(static_cast<unsigned char>(code[j])) || code[j] == '_')) ++j;
    const std::string ident = code.substr(i, j - i);
    const bool multi_letter = ident.size() > 1 && std::isalpha(static_cast<unsigned char>(ident[1]));
    if (keywords && (multi_letter || (j < code.size() && (code[j] == '=' || code[j] == '(' || code[j] == '[')))) {
      // Statement up to the next space outside brackets.
      std::size_t k = i;
      int depth = 0;
      while (k < code.size() && (depth > 0 || !std::isspace(static_cast<unsigned char>(code[k])))) {
        if (code[k] == '(' || code[k] == '[') ++depth;
        if (code[k] == ')' || code[k] == ']') --depth;
        ++k;
      }
      b.keywords.push_back(code.substr(i, k - i));
      i = k;
      continue;
    }
    // Word: one letter and a number.
    Word w;
    w.letter = static_cast<char>(std::toupper(static_cast<unsigned char>(c)));
    std::size_t k = i + 1;
    while (k < code.size() && (std::isdigit(static_cast<unsigned char>(code[k])) || code[k] == '.' || code[k] == '-' ||
                               code[k] == '+')) {
      ++k;
    }
    w.value = code.substr(i + 1, k - i - 1);
    if (!IsNumberText(w.value)) {
      b.error = std::string("word ") + w.letter + " without a number";
      return b;
    }
    if (w.letter == 'N' && b.words.empty() && b.keywords.empty() && b.label.empty()) {
      b.label = "N" + w.value;
    } else {
      b.words.push_back(w);
    }
    i = k;
  }
  return b;
}

}  // namespace tpcal::gcode::internal
