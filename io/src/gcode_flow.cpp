// The O-word structure of a part program (gcode_flow.hpp).

#include "gcode_flow.hpp"

#include <algorithm>
#include <cctype>
#include <optional>

#include "blendbench/core/input_error.hpp"

namespace blendbench::gcode_detail {
namespace {

std::optional<OKind> kind_of(const std::string& keyword) {
  static const std::unordered_map<std::string, OKind> kKinds = {
      {"sub", OKind::kSub},         {"endsub", OKind::kEndsub},     {"call", OKind::kCall},
      {"do", OKind::kDo},           {"while", OKind::kWhile},       {"endwhile", OKind::kEndwhile},
      {"if", OKind::kIf},           {"elseif", OKind::kElseif},     {"else", OKind::kElse},
      {"endif", OKind::kEndif},     {"repeat", OKind::kRepeat},     {"endrepeat", OKind::kEndrepeat},
      {"break", OKind::kBreak},     {"continue", OKind::kContinue}, {"return", OKind::kReturn}};
  const auto it = kKinds.find(keyword);
  if (it == kKinds.end()) return std::nullopt;
  return it->second;
}

bool is_loop(const OLine& o) { return (o.kind == OKind::kWhile && !o.closes_do) || o.kind == OKind::kDo || o.kind == OKind::kRepeat; }

// Matches opening and closing words with a stack of the open structures.
class Matcher {
 public:
  Matcher(Flow& flow, const std::string& file) : flow_(flow), file_(file) {}

  void add(int k) {
    OLine& o = flow_.lines[static_cast<std::size_t>(k)];
    switch (o.kind) {
      case OKind::kSub:
        if (!open_.empty()) fail(o, "a subroutine cannot be defined inside another structure (" + describe(top()) + ")");
        if (const auto it = flow_.subs.find(o.head.label); it != flow_.subs.end()) {
          fail(o, o.head.name() + " is defined twice (first at line " + std::to_string(line_of(it->second)) + ")");
        }
        flow_.subs[o.head.label] = k;
        open_.push_back(k);
        break;
      case OKind::kEndsub: close(o, k, {OKind::kSub}); break;
      case OKind::kDo: case OKind::kIf: case OKind::kRepeat: open_.push_back(k); break;
      case OKind::kWhile:
        // the closing word of a do loop with this label, else a while loop opens
        if (!open_.empty() && top().kind == OKind::kDo && top().head.label == o.head.label) {
          o.closes_do = true;
          close(o, k, {OKind::kDo});
        } else {
          open_.push_back(k);
        }
        break;
      case OKind::kEndwhile: close(o, k, {OKind::kWhile}); break;
      case OKind::kEndrepeat: close(o, k, {OKind::kRepeat}); break;
      case OKind::kElseif: case OKind::kElse: {
        OLine& opener = expect_top(o, {OKind::kIf});
        int last = open_.back();
        while (flow_.lines[static_cast<std::size_t>(last)].next_branch >= 0) last = flow_.lines[static_cast<std::size_t>(last)].next_branch;
        if (flow_.lines[static_cast<std::size_t>(last)].kind == OKind::kElse) {
          fail(o, o.head.name() + " " + o.head.keyword + " after the else of line " + std::to_string(line_of(last)));
        }
        (void)opener;
        flow_.lines[static_cast<std::size_t>(last)].next_branch = k;
        break;
      }
      case OKind::kEndif: {
        expect_top(o, {OKind::kIf});
        for (int b = open_.back(); b >= 0; b = flow_.lines[static_cast<std::size_t>(b)].next_branch) {
          flow_.lines[static_cast<std::size_t>(b)].match = k;
        }
        // the last branch falls through to the endif
        int last = open_.back();
        while (flow_.lines[static_cast<std::size_t>(last)].next_branch >= 0) last = flow_.lines[static_cast<std::size_t>(last)].next_branch;
        flow_.lines[static_cast<std::size_t>(last)].next_branch = k;
        o.match = open_.back();
        open_.pop_back();
        break;
      }
      case OKind::kBreak: case OKind::kContinue: {
        // the innermost loop with this label, inside the current subroutine
        for (auto it = open_.rbegin(); it != open_.rend(); ++it) {
          const OLine& s = flow_.lines[static_cast<std::size_t>(*it)];
          if (s.kind == OKind::kSub) break;
          if (is_loop(s) && s.head.label == o.head.label) {
            o.match = *it;
            return;
          }
        }
        fail(o, o.head.name() + " " + o.head.keyword + " is not inside a loop labelled " + o.head.name());
      }
      case OKind::kReturn:
        if (open_.empty() || flow_.lines[static_cast<std::size_t>(open_.front())].kind != OKind::kSub ||
            flow_.lines[static_cast<std::size_t>(open_.front())].head.label != o.head.label) {
          fail(o, o.head.name() + " return is not inside the subroutine " + o.head.name());
        }
        o.match = open_.front();
        break;
      case OKind::kCall: break;
    }
  }

  void finish() const {
    if (open_.empty()) return;
    const OLine& o = top();
    fail(o, describe(o) + " is not closed (no " + o.head.name() + " " + closer_of(o) + ")");
  }

 private:
  [[noreturn]] void fail(const OLine& o, const std::string& message) const {
    throw InputError(file_, o.line, o.head.column, o.head.name(), message);
  }
  const OLine& top() const { return flow_.lines[static_cast<std::size_t>(open_.back())]; }
  int line_of(int k) const { return flow_.lines[static_cast<std::size_t>(k)].line; }
  std::string describe(const OLine& o) const { return o.head.name() + " " + o.head.keyword + " (line " + std::to_string(o.line) + ")"; }
  static const char* closer_of(const OLine& o) {
    switch (o.kind) {
      case OKind::kSub: return "endsub";
      case OKind::kWhile: return "endwhile";
      case OKind::kDo: return "while";
      case OKind::kRepeat: return "endrepeat";
      default: return "endif";
    }
  }

  // The open structure this closing word belongs to: the innermost, of one of `kinds`, same label.
  OLine& expect_top(const OLine& o, std::initializer_list<OKind> kinds) {
    if (open_.empty()) fail(o, o.head.name() + " " + o.head.keyword + " with nothing open to close");
    OLine& t = flow_.lines[static_cast<std::size_t>(open_.back())];
    const bool kind_ok = std::find(kinds.begin(), kinds.end(), t.kind) != kinds.end() && !(t.kind == OKind::kWhile && t.closes_do);
    if (!kind_ok || t.head.label != o.head.label) {
      fail(o, o.head.name() + " " + o.head.keyword + " does not match the innermost open " + describe(t));
    }
    return t;
  }

  void close(OLine& o, int k, std::initializer_list<OKind> kinds) {
    OLine& opener = expect_top(o, kinds);
    opener.match = k;
    o.match = open_.back();
    open_.pop_back();
  }

  Flow& flow_;
  const std::string& file_;
  std::vector<int> open_;
};

bool is_blank(char c) { return c == ' ' || c == '\t' || c == '\r' || c == '\f' || c == '\v'; }

}  // namespace

Flow build_flow(std::string_view text, const std::string& file) {
  Flow flow;
  Matcher matcher(flow, file);
  bool seen_code = false;
  int line_no = 0;
  for (std::size_t begin = 0; begin <= text.size(); ++line_no) {
    const std::size_t end = std::min(text.find('\n', begin), text.size());
    const std::string_view line = text.substr(begin, end - begin);
    const std::size_t line_begin = begin;
    begin = end + 1;
    std::size_t first = 0;
    while (first < line.size() && is_blank(line[first])) ++first;
    if (first == line.size()) continue;
    const char c = static_cast<char>(std::toupper(static_cast<unsigned char>(line[first])));
    // the closing tape marker ends the program text
    if (c == '%' && strip_blanks(line) == "%") {
      if (seen_code) break;
      continue;
    }
    seen_code = true;
    if (c != 'O' && c != 'N') continue;
    const CompactLine compact = compact_line(line, line_no + 1, file);
    std::optional<OWordHead> head = oword_head(compact, line_no + 1, file);
    if (!head) continue;
    const std::optional<OKind> kind = kind_of(head->keyword);
    if (!kind) {
      throw InputError(file, line_no + 1, head->column, head->name(),
                       "unknown O-word keyword '" + head->keyword + "' (sub, endsub, call, if, elseif, else, endif, while, "
                       "endwhile, do, repeat, endrepeat, break, continue, return)");
    }
    OLine o;
    o.offset = line_begin;
    o.next = begin;
    o.line = line_no + 1;
    o.head = std::move(*head);
    o.kind = *kind;
    flow.lines.push_back(std::move(o));
    matcher.add(static_cast<int>(flow.lines.size() - 1));
  }
  matcher.finish();
  return flow;
}

}  // namespace blendbench::gcode_detail
