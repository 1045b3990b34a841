#pragma once
// Human-readable quantities for messages and notes: SI values in, text in the units users
// read (mm, deg, 1/mm), six significant digits. The sign of a zero or a NaN means nothing to a
// reader and is not printed ("0 mm", "nan mm"); infinities keep theirs ("-inf mm").

#include <string>
#include <string_view>

namespace blendbench {

std::string format_mm(double metres);          // "12.5 mm"
std::string format_deg(double radians);        // "90 deg"
std::string format_per_mm(double per_metre);   // "0.124 1/mm"
std::string format_mm_per_s(double metres_per_second);  // "250 mm/s"
std::string format_value(double value, int digits = 6);  // "-1e-07": a quantity without a unit

// format_mm's text appended to `out`, without a string of its own (for notes built on the corner
// fits' hot path: a shrunk corner's note costs two of these)
void append_mm(std::string& out, double metres);

// A note on two lengths (m), "<head><first> mm<link><second> mm: <why>", built in one buffer: how
// the transition methods say a corner was shrunk or limited ("deviation shrunk from 0.05 mm to
// 0.0312 mm: the incoming move is short"), on the fits' hot path
std::string lengths_note(std::string_view head, double first, std::string_view link, double second,
                         std::string_view why);

// `text` safe to print on one line of a terminal: control characters (C0, DEL, C1), and bytes
// that are not part of a well-formed UTF-8 sequence, become escapes ("\n", "\t", "\x01",
// "\xff"; a backslash stays itself). Printable ASCII and well-formed UTF-8 (e.g. U+2212) are kept.
std::string printable(std::string_view text);

// Whether `text` is well-formed UTF-8 (RFC 3629; ASCII control characters included): what a JSON
// output can hold. A file name that is not (a byte 0xff) is refused where it enters.
bool is_utf8(std::string_view text);

}  // namespace blendbench
