#include "blendbench/core/note.hpp"

#include <ostream>

#include "blendbench/core/format.hpp"

namespace blendbench {

Note Note::lengths(Literal head, double first, Literal link, double second, Literal why) {
  Note note;
  note.lengths_ = Lengths{head.view(), first, link.view(), second, why.view()};
  return note;
}

std::string Note::text() const {
  if (!lengths_) return rest_;
  const Lengths& l = *lengths_;
  return lengths_note(l.head, l.first, l.link, l.second, l.why) + rest_;
}

std::ostream& operator<<(std::ostream& out, const Note& note) { return out << note.text(); }

}  // namespace blendbench
