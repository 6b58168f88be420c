// Heidenhain TNC 640 Klartext post: no G-words; BEGIN PGM / BLK FORM / TOOL CALL / L / CC / C /
// CYCL DEF blocks, every line numbered from 0. Choices: DIALECTS.md, "Heidenhain".
#include <cmath>

#include "gcode/internal/post_base.h"

namespace tpcal::gcode::internal {
namespace {

class HeidenhainPost : public PostBase {
 public:
  HeidenhainPost(const IrProgram& prog, const GcodeOptions& o) : PostBase(prog, o, NumberStyle::kSigned) {}

 protected:
  bool NumbersEveryLine() const override { return true; }
  std::string Numbered(int n, const std::string& body) const override { return std::to_string(n) + " " + body; }

  std::string PgmLine() const { return "PGM " + o_.program_name + " MM"; }
  void Comment(const std::string& text) { Plain("; " + SanitizeComment(text)); }
  std::string F(double v, int decimals) const { return FormatNumber(v, decimals, NumberStyle::kPlain); }

  void Begin() override {
    Plain("BEGIN " + PgmLine());
    for (const std::string& line : HeaderLines(prog_, o_)) Comment(line);
    const Eigen::Vector3d& lo = prog_.stock_min_mm;
    const Eigen::Vector3d& hi = prog_.stock_max_mm;
    if ((hi - lo).minCoeff() > 0) {
      Plain("BLK FORM 0.1 Z X" + Lin(lo.x()) + " Y" + Lin(lo.y()) + " Z" + Lin(lo.z()));
      Plain("BLK FORM 0.2 X" + Lin(hi.x()) + " Y" + Lin(hi.y()) + " Z" + Lin(hi.z()));
    }
  }

  // A cycle definition: "CYCL DEF n NAME ~" then one Q parameter per continuation line.
  void CycleDef(const std::string& head, const std::vector<std::pair<std::string, std::string>>& q) {
    Block("CYCL DEF " + head + (q.empty() ? "" : " ~"));
    for (std::size_t i = 0; i < q.size(); ++i) {
      Raw("  " + q[i].first + " ;" + q[i].second + (i + 1 < q.size() ? " ~" : ""));
    }
  }

  void Motion(const Instr& in, unsigned mask, const std::string& feed, const std::string& extra = "") {
    const std::string words = AxisWords(in.end, mask);
    if (words.empty() && extra.empty()) return;
    std::string body = "L";
    if (!words.empty()) body += " " + words;
    body += " R0";
    if (!feed.empty()) body += " " + feed;
    if (!extra.empty()) body += " " + extra;
    Block(body);
  }

  std::string FeedF(double mm_per_min) {
    const std::string w = FeedWord("F", mm_per_min, 3);
    return w.empty() ? std::string() : w;
  }

  void SetTcp(bool on) {
    if (on == tcp_) return;
    Block(on ? "M128" : "M129");
    tcp_ = on;
    ForgetAxes(0x7);
    ForgetFeed();
  }

  void Emit(const Instr& in) override {
    const bool motion = in.kind == InstrKind::kRapid || in.kind == InstrKind::kIndex || in.kind == InstrKind::kLinear ||
                        in.kind == InstrKind::kArc || in.kind == InstrKind::kDrillCycle;
    if (motion) SetTcp(o_.five_axis == FiveAxisMode::kToolCenterPoint && InFiveAxisPass(index_));
    switch (in.kind) {
      case InstrKind::kOperationStart:
        Block("; " + SanitizeComment(in.text));
        break;
      case InstrKind::kWorkOffset:
        CycleDef("247 DATUM SETTING", {{"Q339=" + Num(in.work_offset, 0), "DATUM NUMBER"}});
        break;
      case InstrKind::kToolChange: {
        SetTcp(false);
        const double rpm = NextSpindleRpm(index_);
        tool_rpm_ = Rpm(rpm);
        Block("TOOL CALL " + std::to_string(Tool(in.tool_index).number) + " Z S" + tool_rpm_);
        ForgetAxes(0x3F);
        ForgetFeed();
        break;
      }
      case InstrKind::kSpindleOn: {
        const std::string s = Rpm(in.spindle_rpm);
        if (s != tool_rpm_) {
          Block("TOOL CALL Z S" + s);
          tool_rpm_ = s;
        }
        Block(in.spindle_clockwise ? "M3" : "M4");
        break;
      }
      case InstrKind::kSpindleOff:
        Block("M5");
        break;
      case InstrKind::kCoolantOn:
        Block(o_.coolant == Coolant::kMist ? "M7" : "M8");
        break;
      case InstrKind::kCoolantOff:
        Block("M9");
        break;
      case InstrKind::kRapid:
      case InstrKind::kIndex:
        Motion(in, in.axis_mask, "FMAX");
        break;
      case InstrKind::kLinear:
        if (in.feed_mode == FeedMode::kPerRevolution) {
          Motion(in, 0x3F, FeedWord("FU", in.feed_mm_per_rev, 4));
        } else if (in.feed_mode == FeedMode::kInverseTime) {
          // No inverse time on the TNC: with M128 F is the tool-tip feed; without it, the
          // feed of the linear axes (rotary axes follow), see DIALECTS.md.
          const double len = tcp_ ? in.tip_path_mm
                                  : std::sqrt(std::pow(in.end.x_mm - in.start.x_mm, 2) +
                                              std::pow(in.end.y_mm - in.start.y_mm, 2) +
                                              std::pow(in.end.z_mm - in.start.z_mm, 2));
          Motion(in, 0x3F, FeedF(std::max(len, 1e-3) / in.duration_s * 60.0));
        } else {
          Motion(in, 0x3F, FeedF(in.feed_mm_per_min));
        }
        break;
      case InstrKind::kArc: {
        // A circle outside the working plane (tool axis Z): CC and C name the plane's two axes.
        const unsigned in_plane = in.arc_plane == ArcPlane::kXY ? 0x3u : in.arc_plane == ArcPlane::kZX ? 0x5u : 0x6u;
        const std::string cx = "X" + Lin(in.arc_center_xy_mm.x()), cy = "Y" + Lin(in.arc_center_xy_mm.y());
        const std::string cz = "Z" + Lin(in.arc_center_z_mm);
        const std::string pole = in.arc_plane == ArcPlane::kXY   ? cx + " " + cy
                                 : in.arc_plane == ArcPlane::kZX ? cx + " " + cz
                                                                 : cy + " " + cz;
        Block("CC " + pole);
        std::string body = "C " + AxisWords(in.end, in_plane, true);
        const std::string others = AxisWords(in.end, 0x3Fu & ~in_plane);
        if (!others.empty()) body += " " + others;
        body += std::string(" DR") + (in.clockwise ? "-" : "+") + " R0";
        const std::string f = FeedF(in.feed_mm_per_min);
        if (!f.empty()) body += " " + f;
        Block(body);
        break;
      }
      case InstrKind::kDrillCycle: {
        const DrillCycle& d = in.drill;
        const double q204 = (d.return_to_initial ? d.initial_z_mm : d.r_z_mm) - d.surface_z_mm;
        CycleDef("201 REAMING", {{"Q200=" + Lin(d.r_z_mm - d.surface_z_mm), "SET-UP CLEARANCE"},
                                 {"Q201=" + Lin(d.bottom_z_mm - d.surface_z_mm), "DEPTH"},
                                 {"Q206=" + Num(d.feed_mm_per_min, 3), "FEED RATE FOR PLNGNG"},
                                 {"Q211=" + Num(d.dwell_s, 3), "DWELL TIME AT DEPTH"},
                                 {"Q208=" + Num(d.retract_feed_mm_per_min, 3), "RETRACTION FEED RATE"},
                                 {"Q203=" + Lin(d.surface_z_mm), "SURFACE COORDINATE"},
                                 {"Q204=" + Lin(q204), "2ND SET-UP CLEARANCE"}});
        Block("L " + AxisWords(in.start, 0x3, true) + " R0 FMAX M99");
        AxisWords(in.end);
        ForgetFeed();
        break;
      }
      case InstrKind::kTableSpinStart: {
        if (!spinning_) {
          CycleDef("13.0 ORIENTATION", {});
          Block("CYCL DEF 13.1 ANGLE" + Num(o_.c_spindle.orient_angle_deg, 3));
          Block("M" + std::to_string(o_.c_spindle.orient_mcode));
          if (o_.c_spindle.mode_on_mcode >= 0) Block("M" + std::to_string(o_.c_spindle.mode_on_mcode));
          Block("FUNCTION MODE TURN");
        }
        spin_ = in.spin;
        spinning_ = true;
        if (CssUsable(in.spin)) {
          std::string b = "FUNCTION TURNDATA SPIN VCONST:ON VC:" + F(in.spin.surface_speed_m_per_min, 1);
          if (in.spin.max_rpm > 0) b += " SMAX" + Rpm(in.spin.max_rpm);
          Block(b);
        } else {
          Block("FUNCTION TURNDATA SPIN VCONST:OFF S" + Rpm(in.spin.rpm));
        }
        const int start = o_.c_spindle.heidenhain_start_mcode + (in.spin.positive_c ? 0 : 1);
        Block("M" + std::to_string(start));
        if (o_.c_spindle.heidenhain_x_diameter) {
          x_scale_ = 2.0;
          ForgetAxes(0x1);
        }
        ForgetFeed();
        break;
      }
      case InstrKind::kTableSpinStop:
        Block("M5");
        Block("FUNCTION MODE MILL");
        if (o_.c_spindle.mode_off_mcode >= 0) Block("M" + std::to_string(o_.c_spindle.mode_off_mcode));
        spinning_ = false;
        x_scale_ = 1.0;
        ForgetAxes(0x1 | (1u << 5));
        ForgetFeed();
        break;
      case InstrKind::kDwell:
        Block("CYCL DEF 9.0 DWELL TIME");
        Block("CYCL DEF 9.1 DWELL " + F(in.dwell_s, 3));
        break;
      case InstrKind::kProbe:
        Probe(in);
        break;
      case InstrKind::kProgramStop:
        if (!in.text.empty()) Comment(in.text);
        Block("M0");
        break;
      case InstrKind::kProgramEnd:
        SetTcp(false);
        Block("M30");
        break;
    }
  }

  // A probe move along one machine axis: touch probe cycle 0 (REF. PLANE): rapid to the
  // pre-positioning point (TCH PROBE 0.1, the approach point), probe along that axis at the probe
  // table's feed, store the coordinate in Q<n>, retract to the pre-positioning point. The probing
  // distance is the probe table's DIST.
  // Any other direction: touch probe cycle 4 (MEASURING IN 3-D) from the current point (the
  // approach point the IR's rapids reached): 4.1 the first of three result parameters (X, Y, Z of
  // the stylus-ball centre, no length or radius compensation), 4.2 the direction vector (the
  // programmed path to the target, mm), 4.3 the maximum measuring path ABST (approach +
  // overtravel), the feed F, the retraction MB (= ABST: back to the start, which the TNC never
  // passes) and BASE0 (results in the active coordinate system, as cycle 0's).
  void Probe(const Instr& in) {
    const Eigen::Vector3d& d = in.probe.direction;
    int axis = 0;
    d.cwiseAbs().maxCoeff(&axis);
    if (std::abs(std::abs(d[axis]) - 1.0) > 1e-12) {
      Probe3d(in);
      return;
    }
    Block("TCH PROBE 0.0 REF. PLANE Q" + std::to_string(in.probe.result) + " " + std::string(1, "XYZ"[axis]) +
          (d[axis] > 0 ? "+" : "-"));
    Block("TCH PROBE 0.1 " + AxisWords(in.start, 0x7, /*force=*/true));
    ForgetFeed();
  }

  // Cycle 4's result parameters of touch n: Q(30 + 3 (n - 1)) .. +2, clear of cycle 0's Q<n>
  // (n < 30) and within the user range Q0..Q99 (n <= 23).
  static constexpr int kProbe3dFirstQ = 30;
  static constexpr int kProbe3dLastQ = 99;

  void Probe3d(const Instr& in) {
    const int q = kProbe3dFirstQ + 3 * (in.probe.result - 1);
    if (in.probe.result < 1 || q + 2 > kProbe3dLastQ) {
      Fail({StatusCode::kInvalidArgument, "Heidenhain: touch " + std::to_string(in.probe.result) +
                                              " of a position: touch probe cycle 4's results Q" + std::to_string(q) +
                                              ".. leave Q" + std::to_string(kProbe3dFirstQ) + "..Q" +
                                              std::to_string(kProbe3dLastQ)});
      return;
    }
    const Eigen::Vector3d path(in.end.x_mm - in.start.x_mm, in.end.y_mm - in.start.y_mm, in.end.z_mm - in.start.z_mm);
    Block("TCH PROBE 4.0 MEASURING IN 3-D");
    Block("TCH PROBE 4.1 Q" + std::to_string(q));
    Block("TCH PROBE 4.2 IX" + Lin(path.x()) + " IY" + Lin(path.y()) + " IZ" + Lin(path.z()));
    const std::string dist = FormatNumber(path.norm(), o_.linear_decimals, NumberStyle::kPlain);
    Block("TCH PROBE 4.3 ABST+" + dist + " F" + F(in.feed_mm_per_min, 3) + " MB" + dist + " BASE0");
    ForgetAxes(0x7);  // the retract to the start is written in full
    ForgetFeed();
  }

  void End() override { Plain("END " + PgmLine()); }

 private:
  std::string tool_rpm_;
};

}  // namespace

std::unique_ptr<PostBase> MakeHeidenhainPost(const IrProgram& prog, const GcodeOptions& o) {
  return std::make_unique<HeidenhainPost>(prog, o);
}

}  // namespace tpcal::gcode::internal
