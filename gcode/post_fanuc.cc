// ISO / Fanuc (M series) post. Choices: DIALECTS.md, "Fanuc".
#include <cmath>

#include "gcode/internal/post_gstyle.h"

namespace tpcal::gcode::internal {
namespace {

class FanucPost : public GStylePost {
 public:
  FanucPost(const IrProgram& prog, const GcodeOptions& o) : GStylePost(prog, o, NumberStyle::kPoint) {}

 protected:
  std::string G(int code) const override { return code < 10 ? "G0" + std::to_string(code) : "G" + std::to_string(code); }
  std::string M(int code) const override { return code < 10 ? "M0" + std::to_string(code) : "M" + std::to_string(code); }

  void Comment(const std::string& text) override { Plain("(" + Upper(SanitizeComment(text)) + ")"); }

  void Begin() override {
    Plain("%");
    char num[16];
    std::snprintf(num, sizeof(num), "O%04d", o_.program_number);
    Plain(std::string(num) + " (" + o_.program_name + ")");
    for (const std::string& line : HeaderLines(prog_, o_)) Comment(line);
  }

  void Setup(const Instr& in) override {
    Block("G21");
    Block("G17 G40 G49 G80 G90 G94");
    Block("G" + std::to_string(53 + in.work_offset));
  }

  void ToolChange(const IrTool& tool) override { Block("T" + std::to_string(tool.number) + " M06"); }
  std::string LengthCompWords(const IrTool& tool) const override { return "G43 H" + std::to_string(tool.number); }

  void Cycle(const Instr& in) override {
    const DrillCycle& d = in.drill;
    Block(std::string(d.return_to_initial ? "G98" : "G99") + " G85 X" + Lin(d.x_mm) + " Y" + Lin(d.y_mm) + " Z" +
          Lin(d.bottom_z_mm) + " R" + Lin(d.r_z_mm) + " F" + FormatNumber(d.feed_mm_per_min, 3, NumberStyle::kPoint));
    Block("G80");
    ForgetFeed();
  }

  // G31 skip function (one shot): feed toward the target, stop on the skip signal (#5061..).
  void Probe(const Instr& in) override { ProbeBlock(G(31), in); }

  void SpinStart(const TableSpin& spin, bool restart) override {
    if (!restart) {
      Block(M(o_.c_spindle.orient_mcode));
      if (o_.c_spindle.mode_on_mcode >= 0) Block(M(o_.c_spindle.mode_on_mcode));
    }
    const int dir = spin.positive_c ? o_.c_spindle.positive_c_mcode : 7 - o_.c_spindle.positive_c_mcode;
    if (CssUsable(spin)) {
      if (spin.max_rpm > 0) Block("G92 S" + Rpm(spin.max_rpm));
      Block("G96 P" + std::to_string(kinematics::AxisIndex(spin.radius_axis) + 1) + " S" +
            Rpm(spin.surface_speed_m_per_min) + " " + M(dir));
    } else {
      Block("G97 S" + Rpm(spin.rpm) + " " + M(dir));
    }
  }

  void SpinStop() override {
    Block(M(5));
    Block("G97");
    if (o_.c_spindle.mode_off_mcode >= 0) Block(M(o_.c_spindle.mode_off_mcode));
  }

  void Dwell(double seconds) override { Block("G04 X" + FormatNumber(seconds, 3, NumberStyle::kPoint)); }

  // Tool centre point control, type 1 (rotary axis positions); the programming coordinate
  // system must follow the table (parameter 19696#5 on 30i), see DIALECTS.md.
  void TcpOn(const IrTool& tool) override { Block("G43.4 H" + std::to_string(tool.number)); }
  void TcpOff(const IrTool& tool) override {
    Block("G49");
    length_pending_ = true;
  }

  void ProgramEnd() override { Block("M30"); }
  void End() override { Plain("%"); }
};

}  // namespace

std::unique_ptr<PostBase> MakeFanucPost(const IrProgram& prog, const GcodeOptions& o) {
  return std::make_unique<FanucPost>(prog, o);
}

}  // namespace tpcal::gcode::internal
