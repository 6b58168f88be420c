#include "core/base64.h"

#include <array>
#include <cstdint>

namespace tpcal {
namespace {

constexpr char kAlphabet[] = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";

constexpr std::array<std::int8_t, 256> kValue = [] {
  std::array<std::int8_t, 256> t{};
  t.fill(-1);
  for (int i = 0; i < 64; ++i) t[static_cast<unsigned char>(kAlphabet[i])] = static_cast<std::int8_t>(i);
  return t;
}();

bool IsBlank(char c) { return c == ' ' || c == '\t' || c == '\n' || c == '\r'; }

}  // namespace

std::optional<std::string> DecodeBase64(std::string_view text, std::size_t* bad_offset) {
  std::string out;
  out.reserve(text.size() / 4 * 3);
  std::uint32_t acc = 0;
  int have = 0, pad = 0;  // characters of the current group, '=' seen
  for (std::size_t i = 0; i < text.size(); ++i) {
    const char c = text[i];
    if (IsBlank(c)) continue;
    const std::int8_t v = kValue[static_cast<unsigned char>(c)];
    const bool bad = c == '=' ? (have < 2 || have + pad >= 4) : (v < 0 || pad != 0);
    if (bad) {
      *bad_offset = i;
      return std::nullopt;
    }
    if (c == '=') {
      ++pad;
      continue;
    }
    acc = (acc << 6) | static_cast<std::uint32_t>(v);
    if (++have == 4) {
      out.push_back(static_cast<char>((acc >> 16) & 0xFF));
      out.push_back(static_cast<char>((acc >> 8) & 0xFF));
      out.push_back(static_cast<char>(acc & 0xFF));
      acc = 0;
      have = 0;
    }
  }
  if (have == 2 && pad == 2) {
    out.push_back(static_cast<char>((acc >> 4) & 0xFF));
  } else if (have == 3 && pad == 1) {
    out.push_back(static_cast<char>((acc >> 10) & 0xFF));
    out.push_back(static_cast<char>((acc >> 2) & 0xFF));
  } else if (have != 0 || pad != 0) {
    *bad_offset = text.size();
    return std::nullopt;
  }
  return out;
}

std::string EncodeBase64(std::string_view bytes) {
  std::string out;
  out.reserve((bytes.size() + 2) / 3 * 4);
  std::size_t i = 0;
  auto byte = [&](std::size_t k) { return static_cast<std::uint32_t>(static_cast<unsigned char>(bytes[k])); };
  for (; i + 3 <= bytes.size(); i += 3) {
    const std::uint32_t g = (byte(i) << 16) | (byte(i + 1) << 8) | byte(i + 2);
    for (int s = 18; s >= 0; s -= 6) out.push_back(kAlphabet[(g >> s) & 0x3F]);
  }
  const std::size_t rest = bytes.size() - i;
  if (rest == 0) return out;
  const std::uint32_t g = (byte(i) << 16) | (rest == 2 ? byte(i + 1) << 8 : 0);
  out.push_back(kAlphabet[(g >> 18) & 0x3F]);
  out.push_back(kAlphabet[(g >> 12) & 0x3F]);
  out.push_back(rest == 2 ? kAlphabet[(g >> 6) & 0x3F] : '=');
  out.push_back('=');
  return out;
}

}  // namespace tpcal
