// POV-Ray bicubic_patch reader: a small tokenizer (comments, strings, names, numbers, single
// characters) and a parser that looks only inside bicubic_patch blocks.
#include "core/io/patch_io.h"

#include <charconv>
#include <cmath>
#include <initializer_list>
#include <limits>
#include <optional>

#include "core/io/file_util.h"
#include "core/scene/scene_build.h"

namespace frameless {
namespace {

enum class Kind { End, Name, Number, String, Char };

struct Token {
  Kind kind = Kind::End;
  std::string_view text;
  size_t line = 0;
};

bool is_name_start(char c) { return (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || c == '_'; }
bool is_digit(char c) { return c >= '0' && c <= '9'; }
bool is_name_char(char c) { return is_name_start(c) || is_digit(c); }

// At most 32 characters of a token, non-printable bytes as \xNN, for messages.
std::string quote(std::string_view s) {
  std::string out = "'";
  for (char c : s.substr(0, 32)) {
    if (c >= 0x20 && c < 0x7f) {
      out += c;
    } else {
      static const char kHex[] = "0123456789abcdef";
      out += "\\x";
      out += kHex[(unsigned char)c >> 4];
      out += kHex[c & 15];
    }
  }
  return out + (s.size() > 32 ? "...'" : "'");
}

class Lexer {
 public:
  Lexer(std::string_view text, const std::string& name) : s_(text), name_(name) {}

  // The next token; false (with error()) for an unterminated comment or string.
  bool next(Token& tok) {
    for (;;) {
      while (pos_ < s_.size() && (s_[pos_] == ' ' || s_[pos_] == '\t' || s_[pos_] == '\r' ||
                                  s_[pos_] == '\n' || s_[pos_] == '\v' || s_[pos_] == '\f'))
        line_ += s_[pos_++] == '\n';
      if (pos_ + 1 < s_.size() && s_[pos_] == '/' && s_[pos_ + 1] == '/') {
        while (pos_ < s_.size() && s_[pos_] != '\n') ++pos_;
      } else if (pos_ + 1 < s_.size() && s_[pos_] == '/' && s_[pos_ + 1] == '*') {
        if (!skip_block_comment()) return false;
      } else {
        break;
      }
    }
    tok.line = line_;
    const size_t start = pos_;
    if (pos_ == s_.size()) {
      tok.kind = Kind::End;
    } else if (is_name_start(s_[pos_])) {
      while (pos_ < s_.size() && is_name_char(s_[pos_])) ++pos_;
      tok.kind = Kind::Name;
    } else if (is_digit(s_[pos_]) || (s_[pos_] == '.' && pos_ + 1 < s_.size() && is_digit(s_[pos_ + 1]))) {
      // POV-Ray numbers: digits, a fraction, an exponent; signs are operators.
      while (pos_ < s_.size() && is_digit(s_[pos_])) ++pos_;
      if (pos_ < s_.size() && s_[pos_] == '.') ++pos_;
      while (pos_ < s_.size() && is_digit(s_[pos_])) ++pos_;
      if (pos_ < s_.size() && (s_[pos_] == 'e' || s_[pos_] == 'E')) {
        size_t k = pos_ + 1;
        if (k < s_.size() && (s_[k] == '+' || s_[k] == '-')) ++k;
        if (k < s_.size() && is_digit(s_[k])) {
          pos_ = k;
          while (pos_ < s_.size() && is_digit(s_[pos_])) ++pos_;
        }
      }
      tok.kind = Kind::Number;
    } else if (s_[pos_] == '"') {
      // Strings are skipped whole, so that braces or names inside them mean nothing.
      for (++pos_; pos_ < s_.size() && s_[pos_] != '"'; ++pos_) {
        if (s_[pos_] == '\\' && pos_ + 1 < s_.size() && s_[pos_ + 1] != '\n') ++pos_;
        line_ += s_[pos_] == '\n';
      }
      if (pos_ == s_.size()) return fail(tok.line, "unterminated string");
      ++pos_;
      tok.kind = Kind::String;
    } else {
      ++pos_;
      tok.kind = Kind::Char;
    }
    tok.text = s_.substr(start, pos_ - start);
    return true;
  }

  const Error& error() const { return *error_; }

  bool fail(size_t line, const std::string& what) {
    error_ = Error{name_ + ":" + std::to_string(line) + ": " + what};
    return false;
  }

 private:
  // POV-Ray block comments nest.
  bool skip_block_comment() {
    const size_t start_line = line_;
    int depth = 0;
    while (pos_ < s_.size()) {
      if (s_.compare(pos_, 2, "/*") == 0) {
        ++depth, pos_ += 2;
      } else if (s_.compare(pos_, 2, "*/") == 0) {
        pos_ += 2;
        if (--depth == 0) return true;
      } else {
        line_ += s_[pos_++] == '\n';
      }
    }
    return fail(start_line, "unterminated /* comment");
  }

  std::string_view s_;
  const std::string& name_;
  size_t pos_ = 0;
  size_t line_ = 1;
  std::optional<Error> error_;
};

bool is_one_of(std::string_view s, std::initializer_list<std::string_view> list) {
  for (std::string_view x : list)
    if (s == x) return true;
  return false;
}

// Appearance blocks after the points, skipped whole.
bool is_modifier(std::string_view s) {
  return is_one_of(s, {"texture", "pigment", "finish", "normal", "interior", "material", "interior_texture"});
}

bool is_transform(std::string_view s) {
  return is_one_of(s, {"translate", "rotate", "scale", "matrix", "transform"});
}

// The keywords a block may start with; their values are ignored.
bool is_patch_keyword(std::string_view s) {
  return is_one_of(s, {"type", "flatness", "u_steps", "v_steps", "accuracy"});
}

class Parser {
 public:
  Parser(std::string_view text, const std::string& name) : lex_(text, name) {}

  Result<std::vector<BezierPatch>> run(const std::string& name) {
    std::vector<BezierPatch> patches;
    for (;;) {
      if (!lex_.next(tok_)) return lex_.error();
      if (tok_.kind == Kind::End) break;
      if (tok_.kind != Kind::Name || tok_.text != "bicubic_patch") continue;
      BezierPatch patch;
      if (!block(patch)) return lex_.error();
      patches.push_back(patch);
    }
    if (patches.empty()) return Error{name + ": no bicubic_patch block"};
    return patches;
  }

 private:
  bool next() { return lex_.next(tok_); }
  bool fail(const std::string& what) {
    std::string m = "bicubic_patch: ";
    m += what;
    return lex_.fail(tok_.line, m);
  }
  bool unterminated() { return lex_.fail(open_line_, "bicubic_patch: block is not closed"); }
  bool is_char(char c) const { return tok_.kind == Kind::Char && tok_.text[0] == c; }

  // bicubic_patch { [keyword value]... 16 x <x, y, z> [modifier]... }
  bool block(BezierPatch& patch) {
    open_line_ = tok_.line;
    if (!next()) return false;
    if (!is_char('{')) return fail("expected '{', got " + quote(tok_.text));
    if (!next()) return false;
    while (tok_.kind == Kind::Name && is_patch_keyword(tok_.text)) {
      // The value is ignored (our tree depth is our own): a number, or a #declared name as the
      // teapot's "flatness Flat_Enough".
      const std::string key(tok_.text);
      if (!next()) return false;
      if (is_char('-') || is_char('+'))
        if (!next()) return false;
      if (tok_.kind == Kind::End) return unterminated();
      if (tok_.kind != Kind::Number && tok_.kind != Kind::Name)
        return fail("'" + key + "' needs a number, got " + quote(tok_.text));
      if (!next()) return false;
    }
    if (is_char(','))  // POV-Ray allows one before the points
      if (!next()) return false;
    int count = 0;
    while (is_char('<')) {
      if (count == 16) return fail("more than 16 control points");
      if (!vector(patch.p[count++])) return false;
      if (!next()) return false;
      if (is_char(','))
        if (!next()) return false;
    }
    if (tok_.kind == Kind::End) return unterminated();
    if (count == 0 && tok_.kind == Kind::Name && !is_modifier(tok_.text) && !is_transform(tok_.text))
      return fail("unknown keyword " + quote(tok_.text));
    if (count != 16) return fail("expected 16 control points, got " + std::to_string(count));
    for (;;) {
      if (tok_.kind == Kind::End) return unterminated();
      if (is_char('}')) return true;
      if (tok_.kind != Kind::Name) return fail("unexpected " + quote(tok_.text));
      if (is_modifier(tok_.text)) {
        if (!skip_braces()) return false;
      } else if (is_transform(tok_.text)) {
        // Ignoring them would put the patch in the wrong place.
        return fail("transforms inside the block are not supported (" + quote(tok_.text) + ")");
      } else if (is_patch_keyword(tok_.text)) {
        return fail(quote(tok_.text) + " must come before the control points");
      } else if (!is_one_of(tok_.text, {"no_shadow", "no_image", "no_reflection", "no_radiosity",
                                        "double_illuminate"})) {
        return fail("unknown keyword " + quote(tok_.text));
      }
      if (!next()) return false;
    }
  }

  // '<' x ',' y ',' z '>' with the '<' current; leaves the '>' current.
  bool vector(Vec3& p) {
    for (int a = 0; a < 3; ++a) {
      if (!next()) return false;
      if (!number(p[a])) return false;
      if (!next()) return false;
      if (tok_.kind == Kind::End) return unterminated();
      if (!is_char(a < 2 ? ',' : '>')) {
        // Appended piece by piece: GCC 12 misreads an operator+ chain here (-Wstringop-overflow).
        std::string m = "malformed vector: expected '";
        m += a < 2 ? ',' : '>';
        m += "', got ";
        m += quote(tok_.text);
        return fail(m);
      }
    }
    return true;
  }

  // [+|-] number, finite in single precision.
  bool number(float& out) {
    bool negative = false;
    if (is_char('-') || is_char('+')) {
      negative = is_char('-');
      if (!next()) return false;
    }
    if (tok_.kind == Kind::End) return unterminated();
    if (tok_.kind == Kind::Name && is_one_of(tok_.text, {"nan", "NaN", "NAN", "inf", "Inf", "INF",
                                                         "infinity", "Infinity"}))
      return fail(quote(tok_.text) + " is not a finite number");
    if (tok_.kind != Kind::Number)
      return fail("malformed vector: expected a number, got " + quote(tok_.text));
    double x = 0.0;
    const auto r = std::from_chars(tok_.text.data(), tok_.text.data() + tok_.text.size(), x);
    if (r.ec != std::errc() || !(std::abs(x) <= std::numeric_limits<float>::max()))
      return fail(quote(tok_.text) + " is not a finite number (single precision)");
    out = float(negative ? -x : x);
    return true;
  }

  // NAME { ... } with NAME current; leaves the closing '}' current.
  bool skip_braces() {
    if (!next()) return false;
    if (!is_char('{')) return fail("expected '{' after the modifier, got " + quote(tok_.text));
    for (int depth = 1; depth > 0;) {
      if (!next()) return false;
      if (tok_.kind == Kind::End) return unterminated();
      depth += is_char('{') - is_char('}');
    }
    return true;
  }

  Lexer lex_;
  Token tok_;
  size_t open_line_ = 0;
};

}  // namespace

Result<std::vector<BezierPatch>> parse_bicubic_patches(std::string_view text, const std::string& name) {
  return one_line(Parser(text, name).run(name));
}

Result<std::vector<BezierPatch>> load_bicubic_patches(const std::string& path) {
  Result<std::string> bytes = read_file_bytes(path);
  if (!bytes) return one_line(Result<std::vector<BezierPatch>>(bytes.error()));
  return parse_bicubic_patches(*bytes, path);
}

}  // namespace frameless
