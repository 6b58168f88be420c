// Word-address (G-code) posts: Fanuc, LinuxCNC, Sinumerik share the motion blocks; each
// dialect supplies its codes and its blocks for tool change, cycles, table turning, dwell, TCP.
#pragma once

#include <string>

#include "gcode/internal/post_base.h"

namespace tpcal::gcode::internal {

class GStylePost : public PostBase {
 public:
  using PostBase::PostBase;

 protected:
  void Emit(const Instr& in) override;

  // Codes: "G0"/"G00" ... (Fanuc writes two digits).
  virtual std::string G(int code) const { return "G" + std::to_string(code); }
  virtual std::string M(int code) const { return "M" + std::to_string(code); }
  virtual void Comment(const std::string& text) = 0;
  virtual void Setup(const Instr& in) = 0;           // units, plane, modes, work offset
  virtual void ToolChange(const IrTool& tool) = 0;
  virtual std::string LengthCompWords(const IrTool& tool) const = 0;  // with the first Z rapid
  virtual void Cycle(const Instr& in) = 0;
  // One touch-probe move (InstrKind::kProbe): the dialect's probing block toward in.end.
  virtual void Probe(const Instr& in) = 0;
  // `restart`: the table already spins (a new pass needs another radius axis or speed).
  virtual void SpinStart(const TableSpin& spin, bool restart) = 0;
  virtual void SpinStop() = 0;
  virtual void TurnFeed(const Instr& in);             // default: G95 feed per rev
  virtual void Dwell(double seconds) = 0;
  virtual void TcpOn(const IrTool& tool) = 0;
  virtual void TcpOff(const IrTool& tool) = 0;
  virtual void ProgramEnd() = 0;
  // Inverse-time feed word for a five-axis block (G93 F = 1 / minutes).
  virtual std::string FeedModeCode(FeedMode m) const;

  // Emits the feed-mode code if it changes, returns it ("" if unchanged).
  std::string FeedModeWord(FeedMode m);
  void SetTcp(bool on);
  void MotionBlock(const std::string& gcode, const Instr& in, unsigned mask, const std::string& feed);
  // "<prefix> <axis words of in.end> F<feed>" with every linear word written; afterwards the
  // linear axes are unknown (the probe stops where it touches) and the feed is forgotten.
  void ProbeBlock(const std::string& prefix, const Instr& in);

  int tool_ = -1;              // index of the tool in the spindle
  bool length_pending_ = false;
  bool feed_mode_known_ = false;
  FeedMode feed_mode_ = FeedMode::kPerMinute;
  ArcPlane plane_ = ArcPlane::kXY;  // of the last arc (the setup selects G17)
};

}  // namespace tpcal::gcode::internal
