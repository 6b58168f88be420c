// Siemens Sinumerik 840D sl post. Choices: DIALECTS.md, "Sinumerik".
#include <cmath>

#include "gcode/internal/post_gstyle.h"

namespace tpcal::gcode::internal {
namespace {

class SinumerikPost : public GStylePost {
 public:
  SinumerikPost(const IrProgram& prog, const GcodeOptions& o) : GStylePost(prog, o, NumberStyle::kPlain) {}

 protected:
  void Comment(const std::string& text) override { Plain("; " + SanitizeComment(text)); }

  void Begin() override {
    Plain("%_N_" + o_.program_name + "_MPF");
    Plain(";$PATH=/_N_MPF_DIR");
    for (const std::string& line : HeaderLines(prog_, o_)) Comment(line);
  }

  void Setup(const Instr& in) override {
    Block("G17 G71 G90 G94 G40");
    Block("G" + std::to_string(53 + in.work_offset));
  }

  void ToolChange(const IrTool& tool) override { Block("T" + std::to_string(tool.number) + " M6"); }
  std::string LengthCompWords(const IrTool&) const override { return "D1"; }

  // CYCLE85(RTP, RFP, SDIS, DP, DPR, DTB, FFR, RFF) at the current X, Y.
  void Cycle(const Instr& in) override {
    const DrillCycle& d = in.drill;
    const std::string xy = AxisWords(in.start, 0x3);
    if (!xy.empty()) Block("G0 " + xy);
    const double rtp = d.return_to_initial ? d.initial_z_mm : d.r_z_mm;
    Block("CYCLE85(" + Lin(rtp) + "," + Lin(d.surface_z_mm) + "," + Lin(d.r_z_mm - d.surface_z_mm) + "," +
          Lin(d.bottom_z_mm) + ",," + FormatNumber(d.dwell_s, 3) + "," + FormatNumber(d.feed_mm_per_min, 3) + "," +
          FormatNumber(d.retract_feed_mm_per_min, 3) + ")");
    ForgetFeed();
  }

  // MEAS=1: measuring with delete distance-to-go on probe 1's rising edge ($AA_MM / $AA_MW).
  void Probe(const Instr& in) override { ProbeBlock("MEAS=1 G1", in); }

  // SPOS holds the tool spindle; the table spindle becomes the master (SETMS) for S, M3/M4,
  // G96 (with LIMS and the transverse axis SCC) and G95.
  void SpinStart(const TableSpin& spin, bool restart) override {
    if (!restart) {
      Block("SPOS=" + FormatNumber(o_.c_spindle.orient_angle_deg, 3));
      if (o_.c_spindle.mode_on_mcode >= 0) Block(M(o_.c_spindle.mode_on_mcode));
      Block("SETMS(" + std::to_string(o_.c_spindle.spindle_number) + ")");
    }
    const int dir = spin.positive_c ? o_.c_spindle.positive_c_mcode : 7 - o_.c_spindle.positive_c_mcode;
    if (CssUsable(spin)) {
      if (spin.max_rpm > 0) Block("LIMS=" + Rpm(spin.max_rpm));
      Block(std::string("SCC[") + kinematics::AxisLetter(spin.radius_axis) + "]");
      Block("G96 S" + FormatNumber(spin.surface_speed_m_per_min, 1) + " " + M(dir));
    } else {
      Block("G97 S" + Rpm(spin.rpm) + " " + M(dir));
    }
  }

  void SpinStop() override {
    Block("M5");
    Block("G97");
    Block("SETMS");
    Block("M" + std::to_string(o_.c_spindle.spindle_number) + "=70");
    if (o_.c_spindle.mode_off_mcode >= 0) Block(M(o_.c_spindle.mode_off_mcode));
  }

  void Dwell(double seconds) override { Block("G4 F" + FormatNumber(seconds, 3)); }
  void TcpOn(const IrTool&) override { Block("TRAORI"); }
  void TcpOff(const IrTool&) override { Block("TRAFOOF"); }
  void ProgramEnd() override { Block("M30"); }
  void End() override {}
};

}  // namespace

std::unique_ptr<PostBase> MakeSinumerikPost(const IrProgram& prog, const GcodeOptions& o) {
  return std::make_unique<SinumerikPost>(prog, o);
}

}  // namespace tpcal::gcode::internal
