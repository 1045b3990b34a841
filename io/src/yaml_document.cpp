// A YAML document as a tree with positions (yaml_document.hpp), built from libyaml's events.

#include "yaml_document.hpp"

#include <yaml.h>

#include <algorithm>
#include <limits>
#include <optional>
#include <unordered_map>

#include "blendbench/core/input_error.hpp"

namespace blendbench::yaml_detail {

const std::string& Ref::scalar() const {
  static const std::string kEmpty;
  return is_scalar() ? node().text : kEmpty;
}

std::size_t Ref::size() const { return is_sequence() || is_map() ? node().count : 0; }

Ref Ref::operator[](std::size_t i) const { return {doc_, doc_->links_[node().first + i]}; }

Ref Ref::key(std::size_t i) const { return {doc_, doc_->links_[node().first + 2 * i]}; }

Ref Ref::value(std::size_t i) const { return {doc_, doc_->links_[node().first + 2 * i + 1]}; }

Ref Ref::get(std::string_view key_text) const {
  if (!is_map()) return {};
  for (std::size_t i = 0; i < size(); ++i) {
    const std::string& k = key(i).scalar();
    if (k.size() == key_text.size() && std::equal(k.begin(), k.end(), key_text.begin())) return value(i);
  }
  return {};
}

const Node& Ref::node() const { return doc_->nodes_[index_]; }

// The events of libyaml turned into the tree, one at a time; throws on the first problem.
class Builder {
 public:
  Builder(Document& doc, std::string_view text, const std::string& file) : doc_(doc), text_(text), file_(file) {}

  void run() {
    yaml_parser_t parser;
    if (yaml_parser_initialize(&parser) == 0) throw InputError(file_, 0, 0, "", "cannot start the YAML parser (out of memory)");
    struct Closer {
      yaml_parser_t* p;
      ~Closer() { yaml_parser_delete(p); }
    } closer{&parser};
    static const char kNothing = 0;
    const char* data = text_.empty() ? &kNothing : text_.data();
    yaml_parser_set_input_string(&parser, reinterpret_cast<const unsigned char*>(data), text_.size());
    while (true) {
      yaml_event_t event;
      if (yaml_parser_parse(&parser, &event) == 0) parse_error(parser);
      struct EventCloser {
        yaml_event_t* e;
        ~EventCloser() { yaml_event_delete(e); }
      } event_closer{&event};
      if (event.type == YAML_STREAM_END_EVENT) break;
      handle(event);
    }
    // an empty text: a null root
    if (doc_.nodes_.empty()) doc_.nodes_.push_back(Node{});
  }

 private:
  // One open list or map; `children` collects its links until it ends (reused across frames).
  struct Frame {
    std::uint32_t index = 0;
    bool map = false;
    std::vector<std::uint32_t> children;
    std::unordered_map<std::string, std::uint32_t> keys;  // a large map's keys (small ones: a scan)
    std::size_t expanded = 1;                             // nodes below, aliases expanded, and itself
  };
  static constexpr std::size_t kScanKeys = 16;

  [[noreturn]] void fail(int line, int column, const std::string& message) const {
    throw InputError(file_, line, column, path(), message);
  }

  // The key path of what is being read: map keys joined by '.', list items as [i]; `key` is
  // appended (a key being read, not yet in its map).
  std::string path(const std::string& key = "") const {
    std::string out;
    const auto add_key = [&](const std::string& k) {
      if (!out.empty()) out += '.';
      out += k;
    };
    for (int d = 0; d < depth_; ++d) {
      const Frame& f = frames_[static_cast<std::size_t>(d)];
      if (!f.map) {
        out.append("[").append(std::to_string(f.children.size())).append("]");
      } else if (f.children.size() % 2 == 1) {
        // reading the value of the entry whose key came last
        add_key(doc_.nodes_[f.children.back()].text);
      }
    }
    if (!key.empty()) add_key(key);
    return out;
  }

  // Line and column (1-based, in characters) of a byte offset of the text.
  std::pair<int, int> position_of(std::size_t offset) const {
    int line = 1;
    int column = 1;
    for (std::size_t i = 0; i < offset && i < text_.size(); ++i) {
      const auto c = static_cast<unsigned char>(text_[i]);
      if (c == '\n') {
        ++line;
        column = 1;
      } else if ((c & 0xC0) != 0x80) {
        ++column;
      }
    }
    return {line, column};
  }

  [[noreturn]] void parse_error(const yaml_parser_t& p) const {
    const std::string problem = p.problem != nullptr ? p.problem : "unknown problem";
    if (p.error == YAML_READER_ERROR) {
      // bytes that are not text: libyaml gives an offset, not a mark
      const auto [line, column] = position_of(p.problem_offset);
      static constexpr char kHex[] = "0123456789abcdef";
      const auto byte = static_cast<unsigned>(p.problem_value) & 0xFFu;
      fail(line, column, "not a text file: " + problem + " (byte 0x" + kHex[byte >> 4] + kHex[byte & 0xF] + ")");
    }
    const std::string context = p.context != nullptr ? p.context : "";
    const int line = static_cast<int>(p.problem_mark.line) + 1;
    const int column = static_cast<int>(p.problem_mark.column) + 1;
    if (context == "while scanning a quoted scalar" && problem == "found unexpected end of stream") {
      fail(static_cast<int>(p.context_mark.line) + 1, static_cast<int>(p.context_mark.column) + 1,
           "the quoted string that opens here is never closed (the file ends inside it)");
    }
    std::string message = "invalid YAML: " + problem;
    if (!context.empty()) {
      message += " (" + context + " at line " + std::to_string(p.context_mark.line + 1) + ", column " +
                 std::to_string(p.context_mark.column + 1) + ")";
    }
    if (doc_.long_quote_.line > 0 && doc_.long_quote_.line < line) message += long_quote_hint(doc_.long_quote_);
    fail(line, column, message);
  }

  static std::string long_quote_hint(const LongQuote& q) {
    return "; the quoted string at line " + std::to_string(q.line) + ", column " + std::to_string(q.column) + " spans " +
           std::to_string(q.lines) + " lines: is its closing quote missing?";
  }

  void handle(const yaml_event_t& e) {
    const int line = static_cast<int>(e.start_mark.line) + 1;
    const int column = static_cast<int>(e.start_mark.column) + 1;
    switch (e.type) {
      case YAML_DOCUMENT_START_EVENT:
        if (documents_++ > 0) fail(line, column, "a second YAML document: a file holds one ('---' starts another)");
        return;
      case YAML_SCALAR_EVENT: {
        const auto& s = e.data.scalar;
        Node node;
        node.line = line;
        node.column = column;
        node.plain = s.style == YAML_PLAIN_SCALAR_STYLE;
        node.text.assign(reinterpret_cast<const char*>(s.value), s.length);
        const bool null = node.plain && (node.text.empty() || node.text == "~" || node.text == "null" ||
                                         node.text == "Null" || node.text == "NULL");
        node.kind = null ? Kind::kNull : Kind::kScalar;
        if (!node.plain && e.end_mark.line > e.start_mark.line && doc_.long_quote_.line == 0) {
          doc_.long_quote_ = {line, column, static_cast<int>(e.end_mark.line - e.start_mark.line) + 1};
        }
        check_key(node.kind == Kind::kNull ? "an empty key" : nullptr, line, column);
        const std::uint32_t index = add(std::move(node), line, column);
        finish(index, 1, s.anchor != nullptr ? reinterpret_cast<const char*>(s.anchor) : "");
        return;
      }
      case YAML_ALIAS_EVENT: {
        check_key("an alias (*name)", line, column);
        const std::string name = reinterpret_cast<const char*>(e.data.alias.anchor);
        const auto it = anchors_.find(name);
        if (it == anchors_.end()) fail(line, column, "unknown alias *" + name + " (no complete node has the anchor &" + name + ")");
        count(it->second.second, line, column);
        attach(it->second.first, it->second.second, line, column);
        return;
      }
      case YAML_SEQUENCE_START_EVENT:
      case YAML_MAPPING_START_EVENT: {
        const bool map = e.type == YAML_MAPPING_START_EVENT;
        check_key(map ? "a map" : "a list", line, column);
        if (depth_ >= kMaxDepth) {
          fail(line, column, "nested deeper than " + std::to_string(kMaxDepth) + " levels of lists and maps");
        }
        Node node;
        node.kind = map ? Kind::kMap : Kind::kSequence;
        node.line = line;
        node.column = column;
        const std::uint32_t index = add(std::move(node), line, column);
        if (static_cast<std::size_t>(depth_) == frames_.size()) frames_.emplace_back();
        Frame& f = frames_[static_cast<std::size_t>(depth_++)];
        f.index = index;
        f.map = map;
        f.children.clear();
        f.keys.clear();
        f.expanded = 1;
        const unsigned char* anchor = map ? e.data.mapping_start.anchor : e.data.sequence_start.anchor;
        anchor_of_frame_.emplace_back(anchor != nullptr ? reinterpret_cast<const char*>(anchor) : "");
        return;
      }
      case YAML_SEQUENCE_END_EVENT:
      case YAML_MAPPING_END_EVENT: {
        Frame& f = frames_[static_cast<std::size_t>(depth_ - 1)];
        Node& node = doc_.nodes_[f.index];
        node.first = static_cast<std::uint32_t>(doc_.links_.size());
        node.count = static_cast<std::uint32_t>(f.map ? f.children.size() / 2 : f.children.size());
        doc_.links_.insert(doc_.links_.end(), f.children.begin(), f.children.end());
        const std::uint32_t index = f.index;
        const std::size_t expanded = f.expanded;
        const std::string anchor = std::move(anchor_of_frame_.back());
        anchor_of_frame_.pop_back();
        --depth_;
        finish(index, expanded, anchor);
        return;
      }
      default:
        return;
    }
  }

  // Refuses what cannot be a key (`what`, or nullptr when fine) where a map expects one.
  void check_key(const char* what, int line, int column) const {
    if (depth_ == 0) return;
    const Frame& f = frames_[static_cast<std::size_t>(depth_ - 1)];
    if (!f.map || f.children.size() % 2 != 0 || what == nullptr) return;
    fail(line, column, std::string("a key must be a name, not ") + what);
  }

  // Counts `n` more nodes against the limit.
  void count(std::size_t n, int line, int column) {
    total_ += n;
    if (total_ > kMaxNodes) {
      fail(line, column, "more than " + std::to_string(kMaxNodes) + " YAML nodes (aliases counted as the nodes they repeat)");
    }
  }

  std::uint32_t add(Node node, int line, int column) {
    count(1, line, column);
    doc_.nodes_.push_back(std::move(node));
    return static_cast<std::uint32_t>(doc_.nodes_.size() - 1);
  }

  // A node done: remembered under its anchor (if any), attached to the open list or map.
  void finish(std::uint32_t index, std::size_t expanded, const std::string& anchor) {
    if (!anchor.empty()) anchors_[anchor] = {index, expanded};
    const Node& n = doc_.nodes_[index];
    attach(index, expanded, n.line, n.column);
  }

  // Adds a finished node (or an alias's target) to the open list or map.
  void attach(std::uint32_t index, std::size_t expanded, int line, int column) {
    if (depth_ == 0) return;
    Frame& f = frames_[static_cast<std::size_t>(depth_ - 1)];
    if (f.map && f.children.size() % 2 == 0) check_duplicate(f, index, line, column);
    f.children.push_back(index);
    f.expanded += expanded;
  }

  // Refuses the key node `index` when its map `f` has it already.
  void check_duplicate(Frame& f, std::uint32_t index, int line, int column) {
    const std::string& key = doc_.nodes_[index].text;
    const auto refuse = [&](std::uint32_t first) {
      const Node& k = doc_.nodes_[first];
      throw InputError(file_, line, column, path(key),
                       "duplicate key '" + key + "' (first at line " + std::to_string(k.line) + ", column " +
                           std::to_string(k.column) + "); a key may appear once in a map");
    };
    const std::size_t entries = f.children.size() / 2;
    if (entries < kScanKeys) {
      for (std::size_t i = 0; i < f.children.size(); i += 2) {
        if (doc_.nodes_[f.children[i]].text == key) refuse(f.children[i]);
      }
      return;
    }
    if (f.keys.empty()) {
      for (std::size_t i = 0; i < f.children.size(); i += 2) f.keys.emplace(doc_.nodes_[f.children[i]].text, f.children[i]);
    }
    const auto [it, inserted] = f.keys.emplace(key, index);
    if (!inserted) refuse(it->second);
  }

  Document& doc_;
  std::string_view text_;
  const std::string& file_;
  std::vector<Frame> frames_;
  std::vector<std::string> anchor_of_frame_;  // the anchor of each open list or map, "" for none
  int depth_ = 0;
  int documents_ = 0;
  std::size_t total_ = 0;
  std::unordered_map<std::string, std::pair<std::uint32_t, std::size_t>> anchors_;
};

Document::Document(std::string_view text, const std::string& file) {
  if (text.size() >= std::numeric_limits<std::uint32_t>::max()) {
    throw InputError(file, 0, 0, "", "a YAML text of more than 4 GiB");
  }
  Builder(*this, text, file).run();
}

}  // namespace blendbench::yaml_detail
