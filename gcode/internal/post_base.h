// Shared machinery of the dialect posts (not public API): block numbering, labels per IR
// instruction, modal axis / feed words, program coordinates (machine or TCP), table-turning
// helpers.
#pragma once

#include <array>
#include <memory>
#include <string>

#include "gcode/nc_format.h"
#include "gcode/post.h"

namespace tpcal::gcode::internal {

class PostBase {
 public:
  PostBase(const IrProgram& prog, const GcodeOptions& options, NumberStyle style);
  virtual ~PostBase() = default;
  Result<PostedText> Run();

 protected:
  virtual void Begin() = 0;                     // before the first instruction (header, setup)
  virtual void Emit(const Instr& in) = 0;       // one instruction
  virtual void End() = 0;                       // after the last instruction
  // "N10 body" (or "body" without numbering); Heidenhain overrides with its line numbers.
  virtual std::string Numbered(int n, const std::string& body) const;
  virtual bool NumbersEveryLine() const { return false; }

  // A numbered block (returns its label, recorded for the current instruction).
  std::string Block(const std::string& body);
  // An unnumbered line (tape marks, program names, header comments, cycle continuation lines).
  // Dialects that number every line number it too.
  void Plain(const std::string& line);
  // A line appended as it is, never numbered (Heidenhain cycle parameter continuation lines).
  void Raw(const std::string& line) { out_.text += line + "\n"; }
  void Fail(Status s) {
    if (error_.ok()) error_ = std::move(s);
  }

  std::string Lin(double mm) const { return FormatNumber(mm, o_.linear_decimals, style_); }
  std::string Deg(double rad) const;
  std::string Num(double v, int decimals) const { return FormatNumber(v, decimals, style_); }
  std::string Rpm(double rpm) const;

  // Program coordinates of an axis state: X, Y, Z in mm (machine, or the tool tip in the part
  // frame while TCP is on) and A, B, C in degrees.
  std::array<double, 6> ProgramValues(const kinematics::AxisState& s) const;
  // The axis words of `s` whose written value changes (all in `mask` when unknown), separated
  // by spaces, with `letters` (e.g. "X", "Y" ...) and the dialect's number style; updates the
  // modal memory. Rotary words only for axes the machine has.
  std::string AxisWords(const kinematics::AxisState& s, unsigned mask = 0x3F, bool force = false);
  std::string AxisWord(int axis, double value) const;
  void ForgetAxes(unsigned mask);
  bool AxisKnown(int axis) const { return known_[axis]; }
  // The feed word if its text changed (or always when `force`), "" otherwise.
  std::string FeedWord(const std::string& letter, double value, int decimals, bool force = false);
  void ForgetFeed() { last_feed_.clear(); }

  // Table turning: the table speed (rpm) at a cutting radius for the active spin, clamped.
  double SpinRpmAt(const TableSpin& spin, double radius_mm) const;
  bool CssUsable(const TableSpin& spin) const {
    return o_.c_spindle.css && spin.surface_speed_m_per_min > 0 && spin.radius_axis_exact;
  }
  // Whether the instruction at `index` belongs to a five-axis pass (TCP on for the whole pass).
  bool InFiveAxisPass(std::size_t index) const;
  // Next kSpindleOn after `index` (its rpm), or 0.
  double NextSpindleRpm(std::size_t index) const;
  const IrTool& Tool(int index) const { return prog_.tools.at(index); }

  const IrProgram& prog_;
  const GcodeOptions& o_;
  NumberStyle style_;
  std::size_t index_ = 0;  // current instruction
  bool tcp_ = false;
  double x_scale_ = 1.0;   // Heidenhain turning mode writes X as a diameter (2)
  TableSpin spin_;
  bool spinning_ = false;
  PostedText out_;

 private:
  std::array<std::string, 6> last_;
  std::array<bool, 6> known_{};
  std::string last_feed_;
  int next_n_ = 0;
  int line_ = 0;
  Status error_;
};

std::unique_ptr<PostBase> MakeFanucPost(const IrProgram& prog, const GcodeOptions& options);
std::unique_ptr<PostBase> MakeLinuxCncPost(const IrProgram& prog, const GcodeOptions& options);
std::unique_ptr<PostBase> MakeSinumerikPost(const IrProgram& prog, const GcodeOptions& options);
std::unique_ptr<PostBase> MakeHeidenhainPost(const IrProgram& prog, const GcodeOptions& options);

}  // namespace tpcal::gcode::internal
