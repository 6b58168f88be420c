// LinuxCNC RS274NGC post. Choices: DIALECTS.md, "LinuxCNC"; proved by rs274 in the tests.
#include <algorithm>
#include <cmath>

#include "gcode/internal/post_gstyle.h"

namespace tpcal::gcode::internal {
namespace {

class LinuxCncPost : public GStylePost {
 public:
  LinuxCncPost(const IrProgram& prog, const GcodeOptions& o) : GStylePost(prog, o, NumberStyle::kPlain) {}

 protected:
  void Comment(const std::string& text) override { Plain("(" + SanitizeComment(text) + ")"); }

  void Begin() override {
    Plain("%");
    for (const std::string& line : HeaderLines(prog_, o_)) Comment(line);
    Comment("TOOL TABLE: " + (o_.tool_table_file.empty() ? o_.program_name + ".tbl" : o_.tool_table_file) +
            " [LinuxCNC units: inches]");
  }

  void Setup(const Instr& in) override {
    Block("G21 G17 G40 G49 G80 G90 G94");
    // Blending within 1 um: the test piece is cut on the programmed path.
    Block("G" + std::to_string(53 + in.work_offset) + " G64 P0.001");
  }

  void ToolChange(const IrTool& tool) override { Block("T" + std::to_string(tool.number) + " M6"); }
  std::string LengthCompWords(const IrTool& tool) const override { return "G43 H" + std::to_string(tool.number); }

  void Cycle(const Instr& in) override {
    const DrillCycle& d = in.drill;
    Block(std::string(d.return_to_initial ? "G98" : "G99") + " G85 X" + Lin(d.x_mm) + " Y" + Lin(d.y_mm) + " Z" +
          Lin(d.bottom_z_mm) + " R" + Lin(d.r_z_mm) + " F" + FormatNumber(d.feed_mm_per_min, 3));
    Block("G80");
    ForgetFeed();
  }

  // G38.2: probe toward the target, stop on contact, error if none (the contact is in #5061..#5063).
  void Probe(const Instr& in) override { ProbeBlock(G(38) + ".2", in); }

  double Signed(double rpm) const { return spin_.positive_c ? rpm : -rpm; }

  // C as a spindle through motion I/O (rs274 has one spindle and no table turning): M19 holds
  // the tool spindle, M64 P<bit> switches the C drive to velocity mode (the machine's HAL),
  // M68 E<ch> Q<rpm> sets the signed table speed at once, M67 synchronised with the next move.
  void SpinStart(const TableSpin& spin, bool restart) override {
    if (!restart) {
      Block("M19 R" + FormatNumber(o_.c_spindle.orient_angle_deg, 3));
      Block("M64 P" + std::to_string(o_.c_spindle.linuxcnc_mode_bit));
    }
    spin_ = spin;  // Signed() reads the new direction
    last_rpm_ = Rpm(Signed(spin.rpm));
    Block("M68 E" + std::to_string(o_.c_spindle.linuxcnc_speed_channel) + " Q" + last_rpm_);
    rpm_ = std::round(spin.rpm);
  }

  void SpinStop() override {
    Block("M68 E" + std::to_string(o_.c_spindle.linuxcnc_speed_channel) + " Q0");
    Block("M65 P" + std::to_string(o_.c_spindle.linuxcnc_mode_bit));
    Block("M5");
  }

  // Feed per rev as feed per minute at a constant table speed per segment; with constant
  // surface speed the move is split so that the radius changes by at most css_step_mm.
  void TurnFeed(const Instr& in) override {
    const double dr = in.turn_radius_end_mm - in.turn_radius_start_mm;
    const bool css = o_.c_spindle.css && spin_.surface_speed_m_per_min > 0;
    const int n = css ? std::max(1, static_cast<int>(std::ceil(std::abs(dr) / o_.c_spindle.css_step_mm - 1e-9))) : 1;
    for (int k = 0; k < n; ++k) {
      const double f0 = static_cast<double>(k) / n, f1 = static_cast<double>(k + 1) / n;
      const double r_mid = in.turn_radius_start_mm + dr * 0.5 * (f0 + f1);
      const double rpm = std::round(css ? SpinRpmAt(spin_, r_mid) : spin_.rpm);
      const std::string q = Rpm(Signed(rpm));
      if (q != last_rpm_) {
        Block("M67 E" + std::to_string(o_.c_spindle.linuxcnc_speed_channel) + " Q" + q);
        last_rpm_ = q;
      }
      Instr seg = in;
      seg.end.x_mm = in.start.x_mm + (in.end.x_mm - in.start.x_mm) * f1;
      seg.end.y_mm = in.start.y_mm + (in.end.y_mm - in.start.y_mm) * f1;
      seg.end.z_mm = in.start.z_mm + (in.end.z_mm - in.start.z_mm) * f1;
      std::string g = G(1);
      const std::string mode = FeedModeWord(FeedMode::kPerMinute);
      if (!mode.empty()) g += " " + mode;
      MotionBlock(g, seg, 0x3F, FeedWord("F", in.feed_mm_per_rev * rpm, 3));
    }
  }

  void Dwell(double seconds) override { Block("G4 P" + FormatNumber(seconds, 3)); }
  void TcpOn(const IrTool&) override {
    Fail({StatusCode::kInvalidArgument, "LinuxCNC: tool centre point mode is not available (five_axis)"});
  }
  void TcpOff(const IrTool&) override {}
  void ProgramEnd() override { Block("M30"); }
  void End() override { Plain("%"); }

 private:
  std::string last_rpm_;
  double rpm_ = 0.0;
};

}  // namespace

std::unique_ptr<PostBase> MakeLinuxCncPost(const IrProgram& prog, const GcodeOptions& o) {
  return std::make_unique<LinuxCncPost>(prog, o);
}

}  // namespace tpcal::gcode::internal
