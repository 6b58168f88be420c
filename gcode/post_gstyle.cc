#include "gcode/internal/post_gstyle.h"

#include <cmath>

#include "core/units.h"

namespace tpcal::gcode::internal {

std::string GStylePost::FeedModeCode(FeedMode m) const {
  switch (m) {
    case FeedMode::kPerMinute: return G(94);
    case FeedMode::kPerRevolution: return G(95);
    case FeedMode::kInverseTime: return G(93);
  }
  return "";
}

std::string GStylePost::FeedModeWord(FeedMode m) {
  if (feed_mode_known_ && feed_mode_ == m) return "";
  feed_mode_known_ = true;
  feed_mode_ = m;
  ForgetFeed();
  return FeedModeCode(m);
}

void GStylePost::SetTcp(bool on) {
  if (on == tcp_ || tool_ < 0) return;
  if (on) {
    TcpOn(Tool(tool_));
  } else {
    TcpOff(Tool(tool_));
  }
  tcp_ = on;
  ForgetAxes(0x7);  // X, Y, Z change meaning
}

void GStylePost::MotionBlock(const std::string& gcode, const Instr& in, unsigned mask, const std::string& feed) {
  std::string body = gcode;
  if (length_pending_ && tool_ >= 0 && (mask & 0x4)) {
    body += " " + LengthCompWords(Tool(tool_));
    length_pending_ = false;
  }
  const std::string words = AxisWords(in.end, mask);
  if (words.empty() && feed.empty() && body == gcode) return;  // nothing moves
  if (!words.empty()) body += " " + words;
  if (!feed.empty()) body += " " + feed;
  Block(body);
}

void GStylePost::ProbeBlock(const std::string& prefix, const Instr& in) {
  ForgetAxes(0x7);
  Block(prefix + " " + AxisWords(in.end, 0x7) + " " + FeedWord("F", in.feed_mm_per_min, 3, /*force=*/true));
  ForgetAxes(0x7);
  ForgetFeed();
}

void GStylePost::TurnFeed(const Instr& in) {
  std::string g = G(1);
  const std::string mode = FeedModeWord(FeedMode::kPerRevolution);
  if (!mode.empty()) g += " " + mode;
  MotionBlock(g, in, 0x3F, FeedWord("F", in.feed_mm_per_rev, 4));
}

void GStylePost::Emit(const Instr& in) {
  const bool motion = in.kind == InstrKind::kRapid || in.kind == InstrKind::kIndex || in.kind == InstrKind::kLinear ||
                      in.kind == InstrKind::kArc || in.kind == InstrKind::kDrillCycle;
  if (motion) SetTcp(o_.five_axis == FiveAxisMode::kToolCenterPoint && InFiveAxisPass(index_));
  switch (in.kind) {
    case InstrKind::kOperationStart:
      Comment(in.text);
      break;
    case InstrKind::kWorkOffset:
      Setup(in);
      feed_mode_known_ = true;
      feed_mode_ = FeedMode::kPerMinute;
      break;
    case InstrKind::kToolChange:
      SetTcp(false);
      ToolChange(Tool(in.tool_index));
      tool_ = in.tool_index;
      length_pending_ = true;
      ForgetAxes(0x3F);
      break;
    case InstrKind::kSpindleOn:
      Block("S" + Rpm(in.spindle_rpm) + " " + M(in.spindle_clockwise ? 3 : 4));
      break;
    case InstrKind::kSpindleOff:
      Block(M(5));
      break;
    case InstrKind::kCoolantOn:
      Block(M(o_.coolant == Coolant::kMist ? 7 : 8));
      break;
    case InstrKind::kCoolantOff:
      Block(M(9));
      break;
    case InstrKind::kRapid:
    case InstrKind::kIndex:
      MotionBlock(G(0), in, in.axis_mask, "");
      break;
    case InstrKind::kLinear:
      if (in.feed_mode == FeedMode::kPerRevolution) {
        TurnFeed(in);
      } else if (in.feed_mode == FeedMode::kInverseTime) {
        std::string g = G(1);
        const std::string mode = FeedModeWord(FeedMode::kInverseTime);
        if (!mode.empty()) g += " " + mode;
        MotionBlock(g, in, 0x3F, FeedWord("F", 60.0 / in.duration_s, 3, true));
      } else {
        std::string g = G(1);
        const std::string mode = FeedModeWord(FeedMode::kPerMinute);
        if (!mode.empty()) g += " " + mode;
        MotionBlock(g, in, 0x3F, FeedWord("F", in.feed_mm_per_min, 3));
      }
      break;
    case InstrKind::kArc: {
      std::string g = G(in.clockwise ? 2 : 3);
      const std::string mode = FeedModeWord(FeedMode::kPerMinute);
      if (!mode.empty()) g = mode + " " + g;
      if (in.arc_plane != plane_) {  // G17 is the setup's plane
        g = G(in.arc_plane == ArcPlane::kXY ? 17 : in.arc_plane == ArcPlane::kZX ? 18 : 19) + " " + g;
        plane_ = in.arc_plane;
      }
      // The plane's two axes always (a full circle ends where it starts), the others only if they change.
      const unsigned in_plane = in.arc_plane == ArcPlane::kXY ? 0x3u : in.arc_plane == ArcPlane::kZX ? 0x5u : 0x6u;
      std::string body = g + " " + AxisWords(in.end, in_plane, /*force=*/true);
      const std::string others = AxisWords(in.end, 0x3Fu & ~in_plane);
      if (!others.empty()) body += " " + others;
      const std::string i = " I" + Lin(in.arc_center_xy_mm.x() - in.start.x_mm);
      const std::string j = " J" + Lin(in.arc_center_xy_mm.y() - in.start.y_mm);
      const std::string k = " K" + Lin(in.arc_center_z_mm - in.start.z_mm);
      body += in.arc_plane == ArcPlane::kXY ? i + j : in.arc_plane == ArcPlane::kZX ? i + k : j + k;
      const std::string f = FeedWord("F", in.feed_mm_per_min, 3);
      if (!f.empty()) body += " " + f;
      Block(body);
      break;
    }
    case InstrKind::kDrillCycle:
      Cycle(in);
      AxisWords(in.end);  // modal memory: where the cycle leaves the tool
      break;
    case InstrKind::kTableSpinStart:
      SpinStart(in.spin, spinning_);
      spin_ = in.spin;
      spinning_ = true;
      break;
    case InstrKind::kTableSpinStop:
      SpinStop();
      spinning_ = false;
      ForgetAxes(1u << 5);  // the C position is unknown after spindle mode
      break;
    case InstrKind::kDwell:
      Dwell(in.dwell_s);
      break;
    case InstrKind::kProbe:
      Probe(in);
      break;
    case InstrKind::kProgramStop:
      if (!in.text.empty()) Comment(in.text);
      Block(M(0));
      break;
    case InstrKind::kProgramEnd:
      SetTcp(false);
      ProgramEnd();
      break;
  }
}

}  // namespace tpcal::gcode::internal
