#pragma once
// A note for a report, built as text only when it is read. The corner fits say why a parameter
// was shrunk or limited ("deviation 0.0312 mm below the tolerance 0.05 mm: ..."); formatting
// the two lengths costs about 0.11 us, a twentieth of a whole biclothoid fit, and the text is
// needed only where the report is written or printed. So a fit records the lengths and the
// fixed words (Note::lengths), and the text is made there (text()).

#include <iosfwd>
#include <optional>
#include <string>
#include <string_view>
#include <utility>

namespace blendbench {

class Note {
 public:
  // Text that lives as long as the program (a string literal): the only text a deferred note
  // keeps by reference. consteval, so a temporary string cannot be passed by mistake.
  class Literal {
   public:
    consteval Literal(const char* text) : text_(text) {}  // implicit: Note::lengths("shrunk from ", ...)
    std::string_view view() const noexcept { return text_; }

   private:
    std::string_view text_;
  };

  // implicit, so a note is set from text as the string it was: fit.note = "..."
  Note() = default;
  Note(std::string text) : rest_(std::move(text)) {}
  Note(const char* text) : rest_(text) {}

  // "<head><first> mm<link><second> mm: <why>" (first, second in m), as lengths_note
  // (format.hpp) writes it, formatted when text() is called
  static Note lengths(Literal head, double first, Literal link, double second, Literal why);

  bool empty() const noexcept { return !lengths_ && rest_.empty(); }
  void clear() noexcept {
    lengths_.reset();
    rest_.clear();
  }
  // `more` appended to the note's text
  Note& operator+=(std::string_view more) {
    rest_ += more;
    return *this;
  }

  std::string text() const;

  friend bool operator==(const Note& a, const Note& b) { return a.text() == b.text(); }
  friend std::ostream& operator<<(std::ostream& out, const Note& note);

 private:
  struct Lengths {
    std::string_view head;
    double first = 0;
    std::string_view link;
    double second = 0;
    std::string_view why;
  };
  std::optional<Lengths> lengths_;  // the deferred part, which comes first
  std::string rest_;                // text after it (all of the note when there is none)
};

}  // namespace blendbench
