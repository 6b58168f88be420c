#include "gcode/dialect_check.h"

#include <cmath>
#include <cstdlib>
#include <regex>
#include <set>
#include <sstream>

#include "gcode/internal/gstyle_lexer.h"

namespace tpcal::gcode {
namespace {

using internal::LexBlock;
using internal::LexedBlock;
using internal::Lines;
using internal::Trim;

Status BadCheck(int line, const std::string& what) {
  return Status(StatusCode::kParseError, what, "<program>", static_cast<std::size_t>(line));
}

struct GRules {
  std::string letters;
  std::set<double> g;
  std::set<int> m;
  bool decimal_point = false;       // Fanuc: positions and feeds carry a decimal point
  bool upper_comments = false;
  bool keywords = false;            // Sinumerik statements
  bool semicolon_comments = false;
};

GRules RulesFor(const GcodeOptions& o) {
  GRules r;
  const CSpindleOptions& c = o.c_spindle;
  switch (o.dialect) {
    case Dialect::kFanuc:
      r.letters = "NGMXYZABCIJKRFSTHP";
      r.g = {0, 1, 2, 3, 4, 17, 18, 19, 21, 31, 40, 43, 43.4, 49, 54, 55, 56, 57, 58, 59, 80, 85, 90, 92, 93, 94, 95, 96, 97, 98, 99};
      r.m = {0, 3, 4, 5, 6, 7, 8, 9, 30, c.orient_mcode};
      r.decimal_point = true;
      r.upper_comments = true;
      break;
    case Dialect::kLinuxCnc:
      r.letters = "NGMXYZABCIJKRFSTHPQE";
      r.g = {0, 1, 2, 3, 4, 17, 18, 19, 21, 38.2, 40, 43, 49, 54, 55, 56, 57, 58, 59, 64, 80, 85, 90, 93, 94, 98, 99};
      r.m = {0, 3, 4, 5, 6, 7, 8, 9, 19, 30, 64, 65, 67, 68};
      r.semicolon_comments = true;
      break;
    case Dialect::kSinumerik:
      r.letters = "NGMXYZABCIJKFSTD";
      r.g = {0, 1, 2, 3, 4, 17, 18, 19, 40, 54, 55, 56, 57, 71, 90, 93, 94, 95, 96, 97};
      r.m = {0, 3, 4, 5, 6, 7, 8, 9, 30};
      r.keywords = true;
      r.semicolon_comments = true;
      break;
    case Dialect::kHeidenhain:
      break;
  }
  if (o.dialect != Dialect::kLinuxCnc && c.mode_on_mcode >= 0) {
    r.m.insert(c.mode_on_mcode);
    r.m.insert(c.mode_off_mcode);
  }
  return r;
}

bool IsInteger(const std::string& v) { return v.find('.') == std::string::npos; }

Status CheckSinumerikKeyword(int line, const std::string& kw, const GcodeOptions& o) {
  static const std::regex kCycle85(
      R"(CYCLE85\(-?\d+(\.\d+)?,-?\d+(\.\d+)?,\d+(\.\d+)?,-?\d+(\.\d+)?,,\d+(\.\d+)?,\d+(\.\d+)?,\d+(\.\d+)?\))");
  static const std::regex kSpos(R"(SPOS=\d+(\.\d+)?)");
  static const std::regex kSetms(R"(SETMS(\((\d)\))?)");
  static const std::regex kLims(R"(LIMS=\d+)");
  static const std::regex kScc(R"(SCC\[[XYZ]\])");
  static const std::regex kSpindleM(R"(M(\d)=(3|4|5|70))");
  std::smatch m;
  if (kw == "TRAORI" || kw == "TRAFOOF" || kw == "MEAS=1" || std::regex_match(kw, kCycle85) || std::regex_match(kw, kSpos) ||
      std::regex_match(kw, kLims) || std::regex_match(kw, kScc)) {
    return Status::Ok();
  }
  if (std::regex_match(kw, m, kSetms) &&
      (!m[2].matched || std::atoi(m[2].str().c_str()) == o.c_spindle.spindle_number)) {
    return Status::Ok();
  }
  if (std::regex_match(kw, m, kSpindleM) && std::atoi(m[1].str().c_str()) == o.c_spindle.spindle_number) {
    return Status::Ok();
  }
  return BadCheck(line, "statement '" + kw + "' is not in the Sinumerik subset");
}

Result<DialectCheckReport> CheckGStyle(std::string_view text, const GcodeOptions& o) {
  const GRules r = RulesFor(o);
  DialectCheckReport rep;
  const std::vector<std::string> lines = Lines(text);
  std::vector<int> code_lines;
  for (std::size_t i = 0; i < lines.size(); ++i) {
    if (!Trim(lines[i]).empty()) code_lines.push_back(static_cast<int>(i));
  }
  if (code_lines.empty()) return BadCheck(1, "empty program");
  auto line_text = [&](int k) { return Trim(lines[code_lines[k]]); };
  std::size_t first = 0;
  if (o.dialect == Dialect::kFanuc || o.dialect == Dialect::kLinuxCnc) {
    if (line_text(0) != "%") return BadCheck(code_lines[0] + 1, "the program must start with %");
    if (line_text(static_cast<int>(code_lines.size()) - 1) != "%") {
      return BadCheck(code_lines.back() + 1, "the program must end with %");
    }
    first = 1;
  }
  if (o.dialect == Dialect::kFanuc) {
    static const std::regex kO(R"(O\d{4}( \([A-Z0-9_ ]*\))?)");
    if (code_lines.size() < 2 || !std::regex_match(line_text(1), kO)) {
      return BadCheck(code_lines[1] + 1, "expected the program number O0001..O9999");
    }
    first = 2;
  }
  if (o.dialect == Dialect::kSinumerik) {
    if (line_text(0) != "%_N_" + o.program_name + "_MPF") return BadCheck(code_lines[0] + 1, "expected %_N_<NAME>_MPF");
    if (code_lines.size() < 2 || line_text(1) != ";$PATH=/_N_MPF_DIR") return BadCheck(code_lines[1] + 1, "expected ;$PATH");
    first = 2;
  }
  long last_n = -1;
  const std::size_t end = code_lines.size() - ((o.dialect == Dialect::kFanuc || o.dialect == Dialect::kLinuxCnc) ? 1 : 0);
  for (std::size_t k = first; k < end; ++k) {
    const int line = code_lines[k] + 1;
    const std::string t = line_text(static_cast<int>(k));
    ++rep.lines;
    const LexedBlock b = LexBlock(t, r.semicolon_comments, r.keywords);
    if (!b.error.empty()) return BadCheck(line, b.error);
    if (r.upper_comments) {
      for (char ch : b.comment) {
        if (std::islower(static_cast<unsigned char>(ch))) return BadCheck(line, "lower-case letter in a Fanuc comment");
      }
    }
    if (b.comment_only) continue;
    if (!b.label.empty()) {
      const long n = std::strtol(b.label.c_str() + 1, nullptr, 10);
      if (!IsInteger(b.label.substr(1)) || n <= last_n || n > 99999) {
        return BadCheck(line, "block number " + b.label + " must be an integer increasing up to 99999");
      }
      last_n = n;
      ++rep.blocks;
    } else if (o.block_step > 0) {
      return BadCheck(line, "block without an N number");
    }
    for (const std::string& kw : b.keywords) {
      ++rep.words;
      TPCAL_RETURN_IF_ERROR(CheckSinumerikKeyword(line, kw, o));
    }
    std::set<char> seen;
    int motion = 0;
    bool dwell = false;
    for (const auto& w : b.words) {
      ++rep.words;
      if (r.letters.find(w.letter) == std::string::npos) {
        return BadCheck(line, std::string("address ") + w.letter + " is not used in " + DialectName(o.dialect));
      }
      if (w.letter == 'G') {
        const double g = std::strtod(w.value.c_str(), nullptr);
        if (!r.g.count(g)) return BadCheck(line, "G" + w.value + " is not in the " + std::string(DialectName(o.dialect)) + " subset");
        if (g == 0 || g == 1 || g == 2 || g == 3 || g == 31 || g == 38.2 || g == 80 || g == 85) ++motion;
        if (g == 4) dwell = true;
        if (o.dialect == Dialect::kFanuc && g < 10 && w.value.size() != 2) return BadCheck(line, "Fanuc G codes are written G00..G09");
        continue;
      }
      if (w.letter == 'M') {
        if (!IsInteger(w.value) || !r.m.count(std::atoi(w.value.c_str()))) {
          return BadCheck(line, "M" + w.value + " is not in the " + std::string(DialectName(o.dialect)) + " subset");
        }
      }
      if (!seen.insert(w.letter).second) return BadCheck(line, std::string("address ") + w.letter + " twice in one block");
      const bool position = std::string("XYZABCIJRF").find(w.letter) != std::string::npos;
      if (r.decimal_point && position && IsInteger(w.value)) {
        return BadCheck(line, std::string(1, w.letter) + w.value + ": Fanuc positions and feeds need a decimal point");
      }
      if (std::string("MSTHDN").find(w.letter) != std::string::npos && !IsInteger(w.value)) {
        return BadCheck(line, std::string(1, w.letter) + w.value + " must be an integer");
      }
      if (w.letter == 'P' && o.dialect == Dialect::kFanuc && !IsInteger(w.value)) {
        return BadCheck(line, "P" + w.value + " must be an integer");
      }
    }
    if (motion > 1) return BadCheck(line, "two motion codes in one block");
    if (dwell && o.dialect == Dialect::kFanuc && !seen.count('X')) return BadCheck(line, "G04 needs X (seconds)");
  }
  return rep;
}

Result<DialectCheckReport> CheckHeidenhain(std::string_view text, const GcodeOptions& o) {
  DialectCheckReport rep;
  const std::string s = R"([+-]\d+(\.\d+)?)";   // signed number
  const std::string u = R"(\d+(\.\d+)?)";       // unsigned number
  const std::regex kBegin("BEGIN PGM " + o.program_name + " MM");
  const std::regex kEnd("END PGM " + o.program_name + " MM");
  const std::regex kBlk1("BLK FORM 0\\.1 Z X" + s + " Y" + s + " Z" + s);
  const std::regex kBlk2("BLK FORM 0\\.2 X" + s + " Y" + s + " Z" + s);
  const std::regex kTool(R"(TOOL CALL (\d+ )?Z S\d+)");
  const std::regex kL("L( [XYZABC]" + s + ")* R0( (FMAX|F" + u + "|FU" + u + "))?( M\\d+)?");
  // Circles in XY, or (measuring programs) in ZX / YZ outside the working plane.
  const std::string plane = "(X" + s + " Y" + s + "|X" + s + " Z" + s + "|Y" + s + " Z" + s + ")";
  const std::regex kCC("CC " + plane);
  const std::regex kC("C " + plane + "( [XYZABC]" + s + ")* DR[+-] R0( F" + u + ")?");
  const std::regex kM(R"(M(\d+))");
  const std::regex kQ(R"(Q(\d+)=)" + s + R"( ;[A-Z0-9. -]+( ~)?)");
  const std::set<std::string> fixed = {"CYCL DEF 13.0 ORIENTATION", "CYCL DEF 9.0 DWELL TIME", "FUNCTION MODE TURN",
                                       "FUNCTION MODE MILL", "CYCL DEF 247 DATUM SETTING ~", "CYCL DEF 201 REAMING ~"};
  const std::regex kAngle("CYCL DEF 13\\.1 ANGLE" + s);
  const std::regex kDwell("CYCL DEF 9\\.1 DWELL " + u);
  const std::regex kSpin("FUNCTION TURNDATA SPIN (VCONST:ON VC:" + u + "( SMAX\\d+)?|VCONST:OFF S\\d+)");
  const std::regex kG(R"((^| )G\d)");
  const std::regex kProbe0(R"(TCH PROBE 0\.0 REF\. PLANE Q\d+ [XYZ][+-])");
  const std::regex kProbe1("TCH PROBE 0\\.1 X" + s + " Y" + s + " Z" + s);
  // Cycle 4 MEASURING IN 3-D: four blocks in order (4.0 .. 4.3).
  const std::vector<std::regex> kProbe3d = {
      std::regex(R"(TCH PROBE 4\.0 MEASURING IN 3-D)"), std::regex(R"(TCH PROBE 4\.1 Q\d+)"),
      std::regex("TCH PROBE 4\\.2 IX" + s + " IY" + s + " IZ" + s),
      std::regex("TCH PROBE 4\\.3 ABST" + s + " F" + u + " MB" + u + " BASE[01]")};
  std::size_t probe3d_next = 0;  // index of the cycle-4 block expected next (0: none pending)
  std::set<int> m_ok = {0, 3, 4, 5, 7, 8, 9, 30, 99, 128, 129, o.c_spindle.orient_mcode, o.c_spindle.heidenhain_start_mcode,
                        o.c_spindle.heidenhain_start_mcode + 1};
  if (o.c_spindle.mode_on_mcode >= 0) {
    m_ok.insert(o.c_spindle.mode_on_mcode);
    m_ok.insert(o.c_spindle.mode_off_mcode);
  }
  const std::vector<std::string> lines = Lines(text);
  int expect = 0;
  std::vector<int> q_expected;
  int last_line = 0;
  std::string last_body;
  for (std::size_t n = 0; n < lines.size(); ++n) {
    const int line = static_cast<int>(n) + 1;
    const std::string& raw = lines[n];
    if (Trim(raw).empty()) continue;
    ++rep.lines;
    if (!q_expected.empty()) {
      std::smatch m;
      const std::string t = Trim(raw);
      if (!std::isspace(static_cast<unsigned char>(raw[0])) || !std::regex_match(t, m, kQ)) {
        return BadCheck(line, "expected a cycle parameter line 'Qnnn=+v ;NAME'");
      }
      if (std::atoi(m[1].str().c_str()) != q_expected.front()) {
        return BadCheck(line, "expected Q" + std::to_string(q_expected.front()));
      }
      q_expected.erase(q_expected.begin());
      const bool more = t.back() == '~';
      if (more != !q_expected.empty()) return BadCheck(line, "continuation mark '~' must end every parameter line but the last");
      ++rep.words;
      continue;
    }
    std::istringstream ls(raw);
    std::string number;
    ls >> number;
    if (number.empty() || number.find_first_not_of("0123456789") != std::string::npos || std::stoi(number) != expect) {
      return BadCheck(line, "expected line number " + std::to_string(expect));
    }
    ++expect;
    ++rep.blocks;
    std::string body;
    std::getline(ls, body);
    body = Trim(body);
    last_line = line;
    last_body = body;
    if (expect == 1) {
      if (!std::regex_match(body, kBegin)) return BadCheck(line, "expected BEGIN PGM " + o.program_name + " MM");
      continue;
    }
    if (body.rfind(";", 0) == 0) continue;  // comment line
    if (std::regex_search(body, kG)) return BadCheck(line, "G-words do not exist in Klartext: '" + body + "'");
    ++rep.words;
    std::smatch m;
    if (probe3d_next > 0) {
      if (!std::regex_match(body, kProbe3d[probe3d_next])) {
        return BadCheck(line, "expected TCH PROBE 4." + std::to_string(probe3d_next) + " of cycle 4, got '" + body + "'");
      }
      probe3d_next = (probe3d_next + 1) % kProbe3d.size();
      continue;
    }
    if (std::regex_match(body, kProbe3d[0])) {
      probe3d_next = 1;
      continue;
    }
    if (std::regex_match(body, kEnd) || std::regex_match(body, kBlk1) || std::regex_match(body, kBlk2) ||
        std::regex_match(body, kTool) || std::regex_match(body, kCC) || std::regex_match(body, kC) ||
        std::regex_match(body, kAngle) || std::regex_match(body, kDwell) || std::regex_match(body, kSpin) ||
        std::regex_match(body, kProbe0) || std::regex_match(body, kProbe1)) {
      continue;
    }
    if (fixed.count(body)) {
      if (body == "CYCL DEF 247 DATUM SETTING ~") q_expected = {339};
      if (body == "CYCL DEF 201 REAMING ~") q_expected = {200, 201, 206, 211, 208, 203, 204};
      continue;
    }
    if (std::regex_match(body, m, kL)) {
      const std::size_t mpos = body.rfind(" M");
      if (mpos != std::string::npos && !m_ok.count(std::atoi(body.c_str() + mpos + 2))) {
        return BadCheck(line, "M-function in '" + body + "' is not in the Heidenhain subset");
      }
      continue;
    }
    if (std::regex_match(body, m, kM)) {
      if (!m_ok.count(std::atoi(m[1].str().c_str()))) return BadCheck(line, body + " is not in the Heidenhain subset");
      continue;
    }
    return BadCheck(line, "block '" + body + "' is not in the Heidenhain subset");
  }
  if (!q_expected.empty() || probe3d_next > 0) return BadCheck(static_cast<int>(lines.size()), "unfinished cycle definition");
  if (!std::regex_match(last_body, kEnd)) return BadCheck(last_line, "the program must end with END PGM " + o.program_name + " MM");
  return rep;
}

}  // namespace

Result<DialectCheckReport> CheckDialectSyntax(std::string_view text, const GcodeOptions& options) {
  TPCAL_RETURN_IF_ERROR(options.Validate());
  if (options.dialect == Dialect::kHeidenhain) return CheckHeidenhain(text, options);
  return CheckGStyle(text, options);
}

}  // namespace tpcal::gcode
