#pragma once
// Private to io/src (not installed): the parameters of an RS274/NGC program as LinuxCNC keeps
// them (its G-code manual, "Parameters"): numbered #1..#5601, named #<name> local to the
// subroutine call that set them, global #<_name>, and the machine's own (offsets, position),
// which the reader answers through a hook so that there is one copy of each value.

#include <array>
#include <optional>
#include <string>
#include <string_view>
#include <unordered_map>
#include <vector>

namespace blendbench::gcode_detail {

// LinuxCNC's RS274NGC_MAX_PARAMETERS: numbered parameters are #1..#5601.
inline constexpr int kMaxParameter = 5601;
// #1..#30 are the arguments of a subroutine call, local to it.
inline constexpr int kCallArguments = 30;

// The parameters the machine owns (offsets, tool, position): the reader answers reads and
// takes writes of these, in program units, so the program and the interpreter share one value.
class SystemParams {
 public:
  virtual ~SystemParams() = default;
  // The value of numbered parameter n if the machine owns it, else nullopt.
  [[nodiscard]] virtual std::optional<double> read(int n) const = 0;
  // Takes a write of numbered parameter n; false if the machine does not own it.
  virtual bool write(int n, double value) = 0;
  // The value of a predefined named parameter (lower case, e.g. "_x"), else nullopt.
  [[nodiscard]] virtual std::optional<double> read_named(std::string_view name) const = 0;

 protected:
  SystemParams() = default;
  SystemParams(const SystemParams&) = default;
  SystemParams& operator=(const SystemParams&) = default;
};

// All the parameters of one program run. Names are lower case without spaces (as LinuxCNC
// reads them); numbers are checked by the caller to be in 1..kMaxParameter.
class Params {
 public:
  explicit Params(SystemParams& system) : system_(system), numbered_(kMaxParameter + 1, 0.0), frames_(1) {}

  [[nodiscard]] double get(int n) const {
    if (n <= kCallArguments) return frames_.back().args[static_cast<std::size_t>(n - 1)];
    if (const std::optional<double> v = system_.read(n)) return *v;
    return numbered_[static_cast<std::size_t>(n)];
  }
  void set(int n, double value) {
    if (n <= kCallArguments) {
      frames_.back().args[static_cast<std::size_t>(n - 1)] = value;
    } else if (!system_.write(n, value)) {
      numbered_[static_cast<std::size_t>(n)] = value;
    }
  }

  // Predefined names (answered by the machine) first, then names set by the program: a leading
  // '_' makes a name global, any other is local to the current call.
  [[nodiscard]] std::optional<double> named(const std::string& name) const {
    if (const std::optional<double> v = system_.read_named(name)) return v;
    const auto& map = is_global(name) ? globals_ : frames_.back().locals;
    const auto it = map.find(name);
    if (it == map.end()) return std::nullopt;
    return it->second;
  }
  // False when the name is predefined (read-only).
  bool set_named(const std::string& name, double value) {
    if (system_.read_named(name)) return false;
    (is_global(name) ? globals_ : frames_.back().locals)[name] = value;
    return true;
  }

  // A subroutine call: #1..#30 are the arguments (the rest zero), named locals start empty.
  void push_call(const std::vector<double>& args) {
    Frame frame;
    for (std::size_t k = 0; k < args.size() && k < frame.args.size(); ++k) frame.args[k] = args[k];
    frames_.push_back(std::move(frame));
  }
  void pop_call() {
    if (frames_.size() > 1) frames_.pop_back();
  }

 private:
  static bool is_global(const std::string& name) { return !name.empty() && name.front() == '_'; }

  struct Frame {
    std::array<double, kCallArguments> args{};
    std::unordered_map<std::string, double> locals;
  };
  SystemParams& system_;
  std::vector<double> numbered_;
  std::unordered_map<std::string, double> globals_;
  std::vector<Frame> frames_;  // [0]: the main program
};

}  // namespace blendbench::gcode_detail
