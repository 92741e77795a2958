// Whitespace tokenizing shared by the OBJ and PLY readers; pure functions, any thread.
#pragma once
#include <charconv>
#include <cmath>
#include <string_view>

namespace frameless {

// Space, tab, CR, VT, FF (newlines separate lines and are handled by the callers).
inline bool is_space(char c) { return c == ' ' || c == '\t' || c == '\r' || c == '\v' || c == '\f'; }

// s without leading and trailing whitespace.
inline std::string_view trim(std::string_view s) {
  while (!s.empty() && is_space(s.front())) s.remove_prefix(1);
  while (!s.empty() && is_space(s.back())) s.remove_suffix(1);
  return s;
}

// Reads one token as a finite float; a leading '+' is accepted as in C's strtod.
inline bool parse_finite(std::string_view tok, float& out) {
  if (!tok.empty() && tok[0] == '+') tok.remove_prefix(1);
  const auto r = std::from_chars(tok.data(), tok.data() + tok.size(), out);
  return r.ec == std::errc() && r.ptr == tok.data() + tok.size() && std::isfinite(out);
}

// Removes and returns the next whitespace-separated token of s (empty at the end).
inline std::string_view next_token(std::string_view& s) {
  size_t i = 0;
  while (i < s.size() && is_space(s[i])) ++i;
  size_t j = i;
  while (j < s.size() && !is_space(s[j])) ++j;
  std::string_view tok = s.substr(i, j - i);
  s.remove_prefix(j);
  return tok;
}

}  // namespace frameless
