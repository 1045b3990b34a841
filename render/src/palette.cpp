#include <cstdint>
#include <string_view>

#include "blendbench/render/render.hpp"

namespace blendbench {
namespace {

struct MethodColourEntry {
  std::string_view method;
  std::uint32_t rgb;  // 0xrrggbb
};

#include "method_colours.inc"

Rgba from_hex(std::uint32_t rgb) {
  return {static_cast<float>((rgb >> 16) & 0xff) / 255.0f, static_cast<float>((rgb >> 8) & 0xff) / 255.0f,
          static_cast<float>(rgb & 0xff) / 255.0f, 1.0f};
}

}  // namespace

Rgba method_colour(std::string_view method) {
  for (const MethodColourEntry& e : kMethodColourTable) {
    if (e.method == method) return from_hex(e.rgb);
  }
  // as plotio.method_colour picks: the sum of the name's character codes (method names are ASCII)
  std::size_t sum = 0;
  for (const char c : method) sum += static_cast<unsigned char>(c);
  return from_hex(kOtherMethodColours[sum % std::size(kOtherMethodColours)]);
}

}  // namespace blendbench
