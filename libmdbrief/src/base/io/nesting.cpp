#include "mdbrief/internal/base/io/nesting.hpp"

#include <cstring>

namespace mdbrief::internal {

namespace {

bool isSpace(char c) { return c == ' ' || c == '\t' || c == '\r'; }

}  // namespace

bool NestingScan::feed(std::string_view part) {
  for (const char c : part) {
    if (!problem_.empty()) return false;
    if (syntax_ == Syntax::Unknown && !isSpace(c) && c != '\n')
      syntax_ = c == '<' ? Syntax::Xml : Syntax::YamlOrJson;
    if (syntax_ == Syntax::Xml)
      xml(c);
    else
      yaml(c);
    if (c == '\n') ++line_;
    beforeLast_ = last_;
    last_ = c;
  }
  return problem_.empty();
}

void NestingScan::deeper(int level) {
  if (level > kMaxNesting && problem_.empty())
    problem_ = "nested deeper than " + std::to_string(kMaxNesting) + " levels (line " + std::to_string(line_) + ")";
}

int NestingScan::yamlLevel() const {
  const int containers = static_cast<int>(indents_.size()) + markers_ + flow_;
  return containers > 0 ? containers - 1 : 0;
}

void NestingScan::yaml(char c) {
  if (c == '\n') {
    if (pendingMarker_) ++markers_, deeper(yamlLevel());
    if (quoteEnds_) quote_ = 0, quoteEnds_ = false;
    pendingMarker_ = 0;
    markers_ = 0;
    comment_ = false;
    lineStart_ = true;
    entryStart_ = false;
    indent_ = 0;
    previous_ = 0;
    return;
  }
  if (comment_) return;
  // A line that goes on a quoted scalar or a flow collection is no block of its own.
  if (lineStart_ && (quote_ != 0 || flow_ > 0)) lineStart_ = false;
  if (lineStart_) {
    if (isSpace(c)) {
      ++indent_;
      return;
    }
    lineStart_ = false;
    if (c == '#') {
      comment_ = true;
      return;
    }
    while (!indents_.empty() && indents_.back() >= indent_) indents_.pop_back();
    // A flow collection that starts the line is a value: its bracket is its level.
    if (c != '[' && c != '{') indents_.push_back(indent_);
    entryStart_ = true;
    deeper(yamlLevel());
  }
  yamlContent(c);
}

void NestingScan::yamlContent(char c) {
  if (quote_ == '"') {
    if (escaped_)
      escaped_ = false;
    else if (c == '\\')
      escaped_ = true;
    else if (c == '"')
      quote_ = 0, previous_ = c;
    return;
  }
  if (quote_ == '\'') {
    if (!quoteEnds_) {
      quoteEnds_ = c == '\'';
      return;
    }
    quoteEnds_ = false;
    if (c == '\'') return;  // '' is a quote inside the scalar
    quote_ = 0;
    previous_ = '\'';
  }
  if (pendingMarker_) {
    const bool opens = isSpace(c);
    pendingMarker_ = 0;
    if (opens) {
      ++markers_;
      deeper(yamlLevel());
      return;  // entryStart_ stays: "- - x" opens two
    }
    entryStart_ = false;
  }
  if (isSpace(c)) return;
  if (c == '#' && (last_ == '\n' || isSpace(last_))) {
    comment_ = true;
    return;
  }
  if (entryStart_ && flow_ == 0 && (c == '-' || c == '?')) {
    pendingMarker_ = c;
    previous_ = c;
    return;
  }
  entryStart_ = false;
  // Brackets and quotes open where a value starts; elsewhere ("x[y]", "it's") they are text.
  const bool valueStart = previous_ == 0 || std::strchr(":[{,-?", previous_) != nullptr;
  if ((c == '[' || c == '{') && valueStart) {
    ++flow_;
    deeper(yamlLevel());
  } else if ((c == ']' || c == '}') && flow_ > 0) {
    --flow_;
  } else if ((c == '"' || c == '\'') && valueStart) {
    quote_ = c;
    return;
  }
  previous_ = c;
}

void NestingScan::xml(char c) {
  switch (tag_) {
    case Tag::Text:
      if (c == '<') tag_ = Tag::Open;
      return;
    case Tag::Open:
      if (c == '/') {
        tag_ = Tag::Close;
        if (elements_ > 0) --elements_;
      } else if (c == '?') {
        tag_ = Tag::Skip;
      } else if (c == '!') {
        tag_ = Tag::Bang;
        bang_.clear();
      } else {
        tag_ = Tag::Name;
        quote_ = 0;
        if (c == '>') tag_ = Tag::Text;  // "<>": no element
      }
      return;
    case Tag::Name:
      if (quote_ != 0) {
        if (c == quote_) quote_ = 0;
      } else if (c == '"' || c == '\'') {
        quote_ = c;
      } else if (c == '>') {
        tag_ = Tag::Text;
        if (last_ != '/') deeper(++elements_ - 1);
      }
      return;
    case Tag::Bang:
      if (c == '>' && bang_.rfind("[CDATA[", 0) != 0) {
        tag_ = Tag::Text;
        return;
      }
      bang_ += c;
      if (bang_ == "--") tag_ = Tag::Comment;
      else if (bang_ == "[CDATA[") tag_ = Tag::Cdata;
      else if (bang_.size() >= 7) tag_ = Tag::Skip;
      return;
    case Tag::Close:
    case Tag::Skip:
      if (c == '>') tag_ = Tag::Text;
      return;
    case Tag::Comment:
      if (c == '>' && last_ == '-' && beforeLast_ == '-') tag_ = Tag::Text;
      return;
    case Tag::Cdata:
      if (c == '>' && last_ == ']' && beforeLast_ == ']') tag_ = Tag::Text;
      return;
  }
}

std::string nestingProblem(std::string_view text) {
  NestingScan scan;
  scan.feed(text);
  return scan.problem();
}

}  // namespace mdbrief::internal
