#include "gcode/rs274_canon.h"

#include <cctype>
#include <cstdlib>
#include <sstream>

#include "gcode/internal/gstyle_lexer.h"

namespace tpcal::gcode {
namespace {

// Splits "a, b c, d" on commas and spaces (USE_TOOL_LENGTH_OFFSET mixes both).
std::vector<double> Numbers(const std::string& args, bool* ok) {
  std::vector<double> v;
  std::string tok;
  *ok = true;
  auto flush = [&]() {
    if (tok.empty()) return;
    char* end = nullptr;
    const double x = std::strtod(tok.c_str(), &end);
    if (end == tok.c_str() || *end != '\0') *ok = false;
    v.push_back(x);
    tok.clear();
  };
  for (char ch : args) {
    if (ch == ',' || std::isspace(static_cast<unsigned char>(ch))) {
      flush();
    } else {
      tok += ch;
    }
  }
  flush();
  return v;
}

}  // namespace

Result<Rs274Listing> ParseRs274Listing(std::string_view text) {
  Rs274Listing out;
  int plane = 17;
  std::size_t pos = 0;
  int line_no = 0;
  while (pos < text.size()) {
    std::size_t eol = text.find('\n', pos);
    if (eol == std::string_view::npos) eol = text.size();
    const std::string line = internal::Trim(text.substr(pos, eol - pos));
    pos = eol + 1;
    ++line_no;
    if (line.empty()) continue;
    auto bad = [&](const std::string& what) {
      return Status(StatusCode::kParseError, "rs274 listing: " + what + ": '" + line + "'", "<rs274 stdout>",
                    static_cast<std::size_t>(line_no));
    };
    std::istringstream ls(line);
    std::string seq, label;
    ls >> seq >> label;
    if (seq.empty() || !std::isdigit(static_cast<unsigned char>(seq[0])) || label.empty() || label[0] != 'N') {
      return bad("expected '<sequence> <N label> CALL(...)'");
    }
    std::string call;
    std::getline(ls, call);
    call = internal::Trim(call);
    const std::size_t open = call.find('(');
    const std::size_t close = call.rfind(')');
    if (open == std::string::npos || close == std::string::npos || close < open) return bad("expected CALL(...)");
    const std::string name = call.substr(0, open);
    const std::string args = call.substr(open + 1, close - open - 1);
    if (label.find_first_not_of('.', 1) == std::string::npos) label.clear();  // "N....."
    out.calls.emplace_back(label, call);
    bool ok = true;
    if (name == "STRAIGHT_TRAVERSE" || name == "STRAIGHT_FEED" || name == "STRAIGHT_PROBE") {
      const std::vector<double> v = Numbers(args, &ok);
      if (!ok || v.size() < 6) return bad("expected 6 numbers");
      PathMove m;
      m.kind = name == "STRAIGHT_TRAVERSE" ? PathMoveKind::kRapid : PathMoveKind::kFeed;
      for (int i = 0; i < 6; ++i) m.end[i] = v[i];
      m.label = label;
      m.probe = name == "STRAIGHT_PROBE";
      out.path.moves.push_back(m);
      if (m.probe) out.probes.push_back(m);
    } else if (name == "ARC_FEED") {
      const std::vector<double> v = Numbers(args, &ok);
      if (!ok || v.size() < 9) return bad("expected 9 numbers");
      PathMove m;
      m.kind = PathMoveKind::kArc;
      m.plane = plane;
      m.center1_mm = v[2];
      m.center2_mm = v[3];
      m.rotation = static_cast<int>(v[4]);
      std::array<double, 6> end = out.path.moves.empty() ? std::array<double, 6>{} : out.path.moves.back().end;
      if (plane == 17) {
        end[0] = v[0];
        end[1] = v[1];
        end[2] = v[5];
      } else if (plane == 18) {
        end[2] = v[0];
        end[0] = v[1];
        end[1] = v[5];
      } else {
        end[1] = v[0];
        end[2] = v[1];
        end[0] = v[5];
      }
      end[3] = v[6];
      end[4] = v[7];
      end[5] = v[8];
      m.end = end;
      m.label = label;
      out.path.moves.push_back(m);
    } else if (name == "SELECT_PLANE") {
      if (args.find("CANON_PLANE_XY") != std::string::npos) plane = 17;
      else if (args.find("CANON_PLANE_XZ") != std::string::npos) plane = 18;
      else if (args.find("CANON_PLANE_YZ") != std::string::npos) plane = 19;
      else return bad("unknown plane");
    } else if (name == "USE_TOOL_LENGTH_OFFSET") {
      const std::vector<double> v = Numbers(args, &ok);
      if (!ok || v.size() < 3) return bad("expected the offsets");
      out.tool_length_offsets_mm.push_back(v[2]);
      out.path.tool_length_offset_mm = v[2];
    } else if (name == "CHANGE_TOOL") {
      ++out.path.tool_changes;
    } else if (name == "COMMENT") {
      const std::size_t q0 = args.find('"'), q1 = args.rfind('"');
      out.comments.push_back(q0 != std::string::npos && q1 > q0 ? args.substr(q0 + 1, q1 - q0 - 1) : args);
    } else if (name == "PROGRAM_END") {
      out.program_end = true;
    } else if (name == "DWELL") {
      ++out.dwells;
    }
  }
  return out;
}

std::string Rs274Errors(int exit_status, std::string_view stdout_text, std::string_view stderr_text) {
  std::string err;
  std::istringstream es{std::string(stderr_text)};
  std::string line;
  while (std::getline(es, line)) {
    const std::string t = internal::Trim(line);
    if (t.empty() || t == "executing") continue;
    err += (err.empty() ? "" : " | ") + t;
  }
  if (exit_status != 0) err = "rs274 exit status " + std::to_string(exit_status) + (err.empty() ? "" : ": " + err);
  if (err.empty() && stdout_text.find("PROGRAM_END()") == std::string_view::npos) {
    err = "rs274 listing has no PROGRAM_END (the run stopped early)";
  }
  return err;
}

}  // namespace tpcal::gcode
