#include "gcode/nc_reader.h"

#include <cmath>
#include <cstdlib>
#include <map>
#include <sstream>

#include "core/input_echo.h"
#include "gcode/internal/gstyle_lexer.h"

namespace tpcal::gcode {
namespace {

using internal::LexBlock;
using internal::LexedBlock;
using internal::Lines;
using internal::Trim;

double ToD(const std::string& s) { return std::strtod(s.c_str(), nullptr); }

Status BadBlock(int line, const std::string& what) {
  return Status(StatusCode::kParseError, what, "<program>", static_cast<std::size_t>(line));
}

class PathState {
 public:
  NcPath path;
  std::array<double, 6> pos{};
  bool tcp = false;
  std::string label;

  void Move(PathMoveKind kind, const std::array<double, 6>& end) {
    PathMove m;
    m.kind = kind;
    m.end = end;
    m.tcp = tcp;
    m.label = label;
    path.moves.push_back(m);
    pos = end;
  }
  void Arc(const std::array<double, 6>& end, double cx, double cy, int rotation) {
    PathMove m;
    m.kind = PathMoveKind::kArc;
    m.end = end;
    m.tcp = tcp;
    m.plane = 17;
    m.center1_mm = cx;
    m.center2_mm = cy;
    m.rotation = rotation;
    m.label = label;
    path.moves.push_back(m);
    pos = end;
  }
  // Feed in / feed out cycle at the current X, Y: rapid to r, feed to bottom and back to r,
  // rapid to `ret` (when different from r).
  void Ream(double r, double bottom, double ret) {
    std::array<double, 6> p = pos;
    p[2] = r;
    Move(PathMoveKind::kRapid, p);
    p[2] = bottom;
    Move(PathMoveKind::kFeed, p);
    p[2] = r;
    Move(PathMoveKind::kFeed, p);
    if (std::abs(ret - r) > 0) {
      p[2] = ret;
      Move(PathMoveKind::kRapid, p);
    }
  }
};

int AxisIndexOf(char letter) {
  switch (letter) {
    case 'X': return 0;
    case 'Y': return 1;
    case 'Z': return 2;
    case 'A': return 3;
    case 'B': return 4;
    case 'C': return 5;
  }
  return -1;
}

// Fanuc, LinuxCNC, Sinumerik.
Result<NcPath> ReadGStyle(std::string_view text, const GcodeOptions& o) {
  const bool sinumerik = o.dialect == Dialect::kSinumerik;
  const bool semicolon = o.dialect != Dialect::kFanuc;
  PathState st;
  int motion = -1;
  bool cycle = false, ret_initial = true;
  double cycle_r = 0, cycle_z = 0;
  const std::vector<std::string> lines = Lines(text);
  for (std::size_t n = 0; n < lines.size(); ++n) {
    const int line = static_cast<int>(n) + 1;
    const std::string t = Trim(lines[n]);
    if (t.empty() || t == "%") continue;
    if (o.dialect == Dialect::kFanuc && t[0] == 'O') continue;  // program number
    if (sinumerik && (t.rfind("%_N_", 0) == 0 || t[0] == ';')) continue;
    const LexedBlock b = LexBlock(t, semicolon, sinumerik);
    if (!b.error.empty()) return BadBlock(line, b.error + ": '" + EchoInput(t) + "'");
    if (b.comment_only) continue;
    st.label = b.label;
    for (const std::string& kw : b.keywords) {
      if (kw == "TRAORI") {
        st.tcp = true;
      } else if (kw == "TRAFOOF") {
        st.tcp = false;
      } else if (kw.rfind("CYCLE85(", 0) == 0 && kw.back() == ')') {
        std::vector<std::string> args;
        std::string cur;
        for (char ch : kw.substr(8, kw.size() - 9)) {
          if (ch == ',') {
            args.push_back(cur);
            cur.clear();
          } else {
            cur += ch;
          }
        }
        args.push_back(cur);
        if (args.size() < 8 || args[0].empty() || args[1].empty() || args[2].empty() || args[3].empty()) {
          return BadBlock(line, "CYCLE85 needs RTP, RFP, SDIS, DP: '" + EchoInput(kw) + "'");
        }
        const double rtp = ToD(args[0]), rfp = ToD(args[1]), sdis = ToD(args[2]), dp = ToD(args[3]);
        st.Ream(rfp + sdis, dp, rtp);
      } else if (kw.rfind("SPOS=", 0) == 0 || kw.rfind("SETMS", 0) == 0 || kw.rfind("LIMS=", 0) == 0 ||
                 kw.rfind("SCC[", 0) == 0 || (kw.size() > 3 && kw[0] == 'M' && kw.find('=') != std::string::npos)) {
        // spindle statements: no motion
      } else {
        return BadBlock(line, "unknown statement '" + EchoInput(kw) + "'");
      }
    }
    bool dwell = false, cycle_block = false;
    for (const auto& w : b.words) {
      if (w.letter == 'M' && std::abs(ToD(w.value) - 6) < 1e-9) ++st.path.tool_changes;
      if (w.letter != 'G') continue;
      const double g = ToD(w.value);
      if (g == 0 || g == 1 || g == 2 || g == 3) motion = static_cast<int>(g);
      else if (g == 4) dwell = true;
      else if (std::abs(g - 43.4) < 1e-9) st.tcp = true;
      else if (g == 49) st.tcp = false;
      else if (g == 80) cycle = false;
      else if (g == 85) {
        cycle = true;
        cycle_block = true;
      } else if (g == 98) ret_initial = true;
      else if (g == 99) ret_initial = false;
      else if (g == 18 || g == 19) return BadBlock(line, "only the XY plane (G17) is read");
    }
    if (dwell) continue;
    std::array<double, 6> target = st.pos;
    bool axis = false, has_i = false, has_j = false;
    double i_off = 0, j_off = 0;
    for (const auto& w : b.words) {
      const int a = AxisIndexOf(w.letter);
      if (a >= 0) {
        target[a] = ToD(w.value);
        axis = true;
      } else if (w.letter == 'I') {
        i_off = ToD(w.value);
        has_i = true;
      } else if (w.letter == 'J') {
        j_off = ToD(w.value);
        has_j = true;
      } else if (w.letter == 'R' && cycle) {
        cycle_r = ToD(w.value);
        axis = true;
      }
    }
    if (cycle && (cycle_block || axis)) {
      for (const auto& w : b.words) {
        if (w.letter == 'Z') cycle_z = ToD(w.value);
      }
      const double initial = st.pos[2];
      std::array<double, 6> xy = st.pos;
      xy[0] = target[0];
      xy[1] = target[1];
      xy[3] = target[3];
      xy[4] = target[4];
      xy[5] = target[5];
      st.Move(PathMoveKind::kRapid, xy);
      st.Ream(cycle_r, cycle_z, ret_initial ? initial : cycle_r);
      continue;
    }
    if (!axis) continue;
    if (motion == 0) {
      st.Move(PathMoveKind::kRapid, target);
    } else if (motion == 1) {
      st.Move(PathMoveKind::kFeed, target);
    } else if (motion == 2 || motion == 3) {
      if (!has_i || !has_j) return BadBlock(line, "arc without I and J");
      st.Arc(target, st.pos[0] + i_off, st.pos[1] + j_off, motion == 2 ? -1 : 1);
    } else {
      return BadBlock(line, "axis words without a motion mode");
    }
  }
  return std::move(st.path);
}

// Heidenhain Klartext.
Result<NcPath> ReadHeidenhain(std::string_view text, const GcodeOptions& o) {
  PathState st;
  bool turn = false;
  double cc_x = 0, cc_y = 0;
  bool have_cc = false;
  std::map<int, double> q;  // Q parameters of the last CYCL DEF 201
  std::string open_cycle;   // cycle whose continuation lines are being read
  int defined_cycle = 0;
  const std::vector<std::string> lines = Lines(text);
  for (std::size_t n = 0; n < lines.size(); ++n) {
    const int line = static_cast<int>(n) + 1;
    const std::string raw = lines[n];
    if (Trim(raw).empty()) continue;
    if (!open_cycle.empty() && std::isspace(static_cast<unsigned char>(raw[0]))) {
      // Continuation line "  Q200=+2 ;SET-UP CLEARANCE ~".
      const std::string t = Trim(raw);
      if (t.size() < 2 || t[0] != 'Q') return BadBlock(line, "expected a Q parameter line");
      const std::size_t eq = t.find('=');
      if (eq == std::string::npos) return BadBlock(line, "expected Qn=value");
      std::string value = t.substr(eq + 1);
      value = value.substr(0, value.find_first_of(" ;~"));
      q[std::atoi(t.substr(1, eq - 1).c_str())] = ToD(value);
      if (t.back() != '~') open_cycle.clear();
      continue;
    }
    std::istringstream ls(raw);
    std::string number;
    ls >> number;
    if (number.empty() || number.find_first_not_of("0123456789") != std::string::npos) {
      return BadBlock(line, "expected a line number");
    }
    std::string body;
    std::getline(ls, body);
    body = Trim(body);
    st.label = number;
    const std::string code = Trim(body.substr(0, body.find(';')));
    if (code.empty()) continue;  // comment line
    std::istringstream ws(code);
    std::vector<std::string> tok;
    for (std::string w; ws >> w;) tok.push_back(w);
    const std::string& head = tok[0];
    if (head == "BEGIN" || head == "END" || head == "BLK") continue;
    if (head == "TOOL") {
      if (tok.size() > 2 && std::isdigit(static_cast<unsigned char>(tok[2][0]))) ++st.path.tool_changes;  // TOOL CALL n
      continue;
    }
    if (head == "CYCL") {
      if (tok.size() < 3 || tok[1] != "DEF") return BadBlock(line, "expected CYCL DEF");
      if (code.back() == '~') open_cycle = tok[2];
      if (tok[2] == "201") {
        defined_cycle = 201;
        q.clear();
      }
      continue;
    }
    if (head == "FUNCTION") {
      if (code == "FUNCTION MODE TURN") turn = true;
      if (code == "FUNCTION MODE MILL") turn = false;
      continue;
    }
    if (head == "M128") {
      st.tcp = true;
      continue;
    }
    if (head == "M129") {
      st.tcp = false;
      continue;
    }
    if (head[0] == 'M') continue;  // M-functions without motion
    auto value_of = [&](const std::string& w, int a) {
      double v = ToD(w.substr(1));
      if (a == 0 && turn && o.c_spindle.heidenhain_x_diameter) v *= 0.5;
      return v;
    };
    if (head == "CC") {
      for (std::size_t k = 1; k < tok.size(); ++k) {
        if (tok[k][0] == 'X') cc_x = ToD(tok[k].substr(1));
        else if (tok[k][0] == 'Y') cc_y = ToD(tok[k].substr(1));
        else return BadBlock(line, "CC takes X and Y");
      }
      have_cc = true;
      continue;
    }
    if (head == "L" || head == "C") {
      std::array<double, 6> target = st.pos;
      bool rapid = false, call = false;
      int dr = 0;
      for (std::size_t k = 1; k < tok.size(); ++k) {
        const std::string& w = tok[k];
        const int a = AxisIndexOf(w[0]);
        if (a >= 0 && w.size() > 1 && (w[1] == '+' || w[1] == '-')) {
          target[a] = value_of(w, a);
        } else if (w == "FMAX") {
          rapid = true;
        } else if (w == "R0" || w[0] == 'F') {
          // radius compensation off; feeds (F, FU) do not change the path
        } else if (w == "DR+") {
          dr = 1;
        } else if (w == "DR-") {
          dr = -1;
        } else if (w == "M99") {
          call = true;
        } else if (w[0] == 'M') {
        } else {
          return BadBlock(line, "unexpected word '" + EchoInput(w) + "'");
        }
      }
      if (head == "C") {
        if (!have_cc || dr == 0) return BadBlock(line, "arc needs CC and DR+ / DR-");
        st.Arc(target, cc_x, cc_y, dr);
      } else {
        st.Move(rapid ? PathMoveKind::kRapid : PathMoveKind::kFeed, target);
      }
      if (call) {
        if (defined_cycle != 201 || !q.count(200) || !q.count(201) || !q.count(203) || !q.count(204)) {
          return BadBlock(line, "M99 without a complete CYCL DEF 201");
        }
        const double s = q[203];
        st.Ream(s + q[200], s + q[201], s + q[204]);
      }
      continue;
    }
    return BadBlock(line, "unknown block '" + EchoInput(code) + "'");
  }
  return std::move(st.path);
}

}  // namespace

Result<NcPath> ReadNcProgram(std::string_view text, const GcodeOptions& options) {
  if (options.dialect == Dialect::kHeidenhain) return ReadHeidenhain(text, options);
  return ReadGStyle(text, options);
}

}  // namespace tpcal::gcode
