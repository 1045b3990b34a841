#pragma once
// A visitor built from lambdas, for std::visit over the segment variants:
//   std::visit(Overloaded{[](const Line&) {...}, [](const Arc&) {...}}, segment);
// The deduction guide is spelled out: C++20 deduces it for aggregates, but clang 14 does not
// implement that yet.

namespace blendbench {

template <class... Ts>
struct Overloaded : Ts... {
  using Ts::operator()...;
};
template <class... Ts>
Overloaded(Ts...) -> Overloaded<Ts...>;

}  // namespace blendbench
