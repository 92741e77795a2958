// Whitespace tokenizing shared by the OBJ and PLY readers; pure functions, any thread.
#pragma once
#include <string_view>

namespace frameless {

// Space, tab, CR, VT, FF (newlines separate lines and are handled by the callers).
inline bool is_space(char c) { return c == ' ' || c == '\t' || c == '\r' || c == '\v' || c == '\f'; }

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
