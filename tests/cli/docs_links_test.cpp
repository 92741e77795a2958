// The documentation's relative links and images resolve: README.md and docs/*.md name only files
// that exist (links to other sites, mail and anchors in the same page are not checked), and the
// README stays a front page of at most 12 KB.
#include <gtest/gtest.h>

#include <algorithm>
#include <chrono>
#include <cstddef>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <system_error>
#include <vector>

namespace {

namespace fs = std::filesystem;

const fs::path kRoot = fs::path(FRAMELESS_TEST_DATA) / ".." / "..";

std::string read_text(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

// The text without fenced code blocks (``` or ~~~) and with inline code spans blanked out.
std::string prose(const std::string& text) {
  std::string out;
  std::istringstream lines(text);
  std::string line, fence;
  while (std::getline(lines, line)) {
    const size_t first = line.find_first_not_of(" \t");
    const std::string body = first == std::string::npos ? std::string() : line.substr(first);
    if (fence.empty()) {
      if (body.rfind("```", 0) == 0 || body.rfind("~~~", 0) == 0) {
        fence = body.substr(0, body.find_first_not_of(body[0]));
        continue;
      }
      out += line + '\n';
    } else if (body.rfind(fence, 0) == 0 &&
               body.find_first_not_of(std::string(1, fence[0]) + " \t\r") == std::string::npos) {
      fence.clear();  // the closing fence: the same character, at least as many
    }
  }
  // Inline code: a run of n backticks up to the next run of exactly n, blanked (lines kept).
  const auto run_at = [&out](size_t at) {
    size_t n = 0;
    while (at + n < out.size() && out[at + n] == '`') ++n;
    return n;
  };
  for (size_t i = 0; i < out.size();) {
    if (out[i] != '`') { ++i; continue; }
    const size_t n = run_at(i);
    size_t close = std::string::npos;
    for (size_t j = i + n; j < out.size();) {
      if (out[j] != '`') { ++j; continue; }
      const size_t m = run_at(j);
      if (m == n) { close = j; break; }
      j += m;
    }
    if (close == std::string::npos) { i += n; continue; }  // no closing run: literal backticks
    for (size_t k = i; k < close + n; ++k)
      if (out[k] != '\n') out[k] = ' ';
    i = close + n;
  }
  return out;
}

// Every link or image target in markdown text: [text](target "title"), ![alt](target),
// <img src="target">; the title is dropped.
std::vector<std::string> targets(const std::string& text) {
  std::vector<std::string> found;
  for (size_t i = 0; i < text.size(); ++i) {
    if (text[i] != '[') continue;
    int depth = 0;  // the matching ']' (link text may hold brackets, or an image)
    size_t j = i;
    for (; j < text.size(); ++j) {
      if (text[j] == '[') ++depth;
      else if (text[j] == ']' && --depth == 0) break;
      else if (text.compare(j, 2, "\n\n") == 0) j = text.size();  // not across paragraphs
    }
    if (j + 1 >= text.size() || text[j + 1] != '(') continue;
    size_t k = j + 2, parens = 1;
    for (; k < text.size() && parens > 0; ++k) {
      if (text[k] == '(') ++parens;
      else if (text[k] == ')') --parens;
    }
    if (parens > 0) continue;
    std::string inside = text.substr(j + 2, k - 1 - (j + 2));
    const size_t a = inside.find_first_not_of(" \t\n");
    if (a == std::string::npos) continue;
    inside = inside.substr(a);
    if (inside[0] == '<') {
      found.push_back(inside.substr(1, inside.find('>') - 1));
    } else {
      found.push_back(inside.substr(0, inside.find_first_of(" \t\n")));  // the title after it
    }
  }
  for (size_t i = text.find("<img"); i != std::string::npos; i = text.find("<img", i + 1)) {
    const size_t src = text.find("src=", i);
    const size_t end_tag = text.find('>', i);
    if (src == std::string::npos || src > end_tag || src + 5 >= text.size()) continue;
    const char quote = text[src + 4];
    if (quote != '"' && quote != '\'') continue;
    const size_t close = text.find(quote, src + 5);
    if (close != std::string::npos) found.push_back(text.substr(src + 5, close - (src + 5)));
  }
  return found;
}

// The relative targets of markdown file `md` that name no existing file (as written).
std::vector<std::string> broken_links(const fs::path& md) {
  std::vector<std::string> broken;
  for (const std::string& target : targets(prose(read_text(md)))) {
    if (target.empty() || target[0] == '#' || target.rfind("http://", 0) == 0 ||
        target.rfind("https://", 0) == 0 || target.rfind("mailto:", 0) == 0)
      continue;
    const std::string file = target.substr(0, target.find('#'));
    std::error_code ec;
    if (!fs::exists(md.parent_path() / file, ec)) broken.push_back(target);
  }
  return broken;
}

void write_text(const fs::path& p, const std::string& text) {
  std::ofstream out(p, std::ios::binary);
  out << text;
}

std::vector<fs::path> documentation() {
  std::vector<fs::path> files{kRoot / "README.md"};
  for (const auto& entry : fs::directory_iterator(kRoot / "docs"))
    if (entry.path().extension() == ".md") files.push_back(entry.path());
  std::sort(files.begin() + 1, files.end());
  return files;
}

}  // namespace

TEST(DocsLinks, EveryRelativeLinkAndImageResolves) {
  const std::vector<fs::path> files = documentation();
  ASSERT_GE(files.size(), 5u) << "README.md and docs/*.md not found under " << kRoot;
  for (const fs::path& md : files) {
    ASSERT_TRUE(fs::exists(md)) << md;
    for (const std::string& target : broken_links(md))
      ADD_FAILURE() << fs::relative(md, kRoot).string() << ": " << target;
  }
}

TEST(DocsLinks, TheCheckerFindsBrokenLinksAndImagesOnly) {
  const auto stamp = std::chrono::steady_clock::now().time_since_epoch().count();
  const fs::path dir = fs::temp_directory_path() / ("docs_links_test_" + std::to_string(stamp));
  fs::create_directories(dir);
  write_text(dir / "exists.png", "x");
  write_text(dir / "page.md",
             "# Page\n\nA [good link](exists.png \"its title\"), a [broken one](missing.md#part),\n"
             "an [anchor](#page), a [site](https://example.com/x.md), `[code](in_code.md)`.\n\n"
             "![broken image](missing.png)\n\n<img src=\"exists.png\" alt=\"good\">\n\n"
             "```\n[in a fence](in_fence.md)\n```\n\nAfter the fence: [good](./exists.png).\n");
  const std::vector<std::string> broken = broken_links(dir / "page.md");
  fs::remove_all(dir);
  EXPECT_EQ(broken, (std::vector<std::string>{"missing.md#part", "missing.png"}));
}

TEST(DocsLinks, ReadmeIsAFrontPageOfAtMost12KB) {
  EXPECT_LE(fs::file_size(kRoot / "README.md"), 12288u)
      << "README.md is the front page: move details into docs/ and link them";
}
