#pragma once
// How deep the structured text the tools read may nest, checked before a parser sees it (issue
// 45): yaml-cpp stops at 500 levels with "bad file", and OpenCV's FileStorage parsers (XML, YAML,
// JSON) recurse once per level until the stack overflows (at about 40,000 levels in a release
// build, fewer under AddressSanitizer). No file the project reads needs more than a few levels.
// Internal to the build, as atomic_file.hpp.
#include <string>
#include <string_view>
#include <vector>

namespace mdbrief::internal {

inline constexpr int kMaxNesting = 64;

// Follows the nesting of a text given in parts (a decompressed stream) without parsing it. The
// text is XML if its first character other than white space is '<' (as OpenCV tells), else
// YAML or JSON. The top-level map, sequence or element is level 0.
//  - YAML and JSON: flow brackets where a value starts (outside quoted scalars and comments),
//    block indentation and "- " / "? " entries. An estimate: the flow brackets a parser nests
//    into all count; a block entry that opens a map on its line ("- a:") counts one level for
//    two, so that yaml-cpp's own limit (500) stays the last guard of block nesting.
//  - XML: elements open; self-closing tags, comments, CDATA, declarations and processing
//    instructions count none.
class NestingScan {
 public:
  // Scans the next part; false once the text nests deeper than kMaxNesting (problem() says where).
  bool feed(std::string_view part);
  // "" or "nested deeper than 64 levels (line 3)".
  const std::string& problem() const { return problem_; }

 private:
  enum class Syntax { Unknown, YamlOrJson, Xml };
  enum class Tag { Text, Open, Name, Close, Bang, Skip, Comment, Cdata };

  void yaml(char c);
  void yamlContent(char c);
  void xml(char c);
  int yamlLevel() const;
  void deeper(int level);

  Syntax syntax_ = Syntax::Unknown;
  std::string problem_;
  long line_ = 1;
  char last_ = 0, beforeLast_ = 0;  // the two characters before this one
  // YAML and JSON
  std::vector<int> indents_;  // the block indentations open, the current line's last
  int indent_ = 0;            // of the current line so far
  bool lineStart_ = true;     // in the current line's indentation
  bool entryStart_ = false;   // where a "- " or "? " entry may open (after the indentation or another)
  char pendingMarker_ = 0;    // a '-' or '?' that opens an entry if white space follows
  int markers_ = 0;           // the entries the current line opened
  int flow_ = 0;              // open flow brackets
  char quote_ = 0;            // the quote of the scalar being read, or 0
  bool escaped_ = false;      // after a backslash in a double-quoted scalar
  bool quoteEnds_ = false;    // after a ' in a single-quoted scalar: its end, unless a second follows
  bool comment_ = false;
  char previous_ = 0;         // the line's last character outside scalars and white space; 0 at its start
  // XML
  Tag tag_ = Tag::Text;
  int elements_ = 0;
  std::string bang_;  // the start of a "<!" tag, until it tells a comment or CDATA
};

// NestingScan over a whole text: "" or the problem.
std::string nestingProblem(std::string_view text);

}  // namespace mdbrief::internal
