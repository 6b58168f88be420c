// Quoting of input bytes in error messages: the one helper every reader uses, so a hostile file
// can neither flood stderr (or a batch's summary.csv) nor put control bytes or broken UTF-8
// into it; and the UTF-8 check of labels that end up in JSON.
#pragma once

#include <cstddef>
#include <string>
#include <string_view>

namespace tpcal {

// Bytes of input quoted in an error message at most.
inline constexpr std::size_t kMaxEchoBytes = 80;

// `bytes` for a message: at most `max_bytes` of it (cut at a character boundary, then "..."),
// control bytes, DEL and bytes that are not valid UTF-8 written as \xNN (tab as \t, and a
// backslash stays a backslash). Never fails.
std::string EchoInput(std::string_view bytes, std::size_t max_bytes = kMaxEchoBytes);

// Offset of the first byte of `text` that does not start a valid UTF-8 sequence (overlong forms,
// surrogates and code points above U+10FFFF are invalid), or std::string_view::npos if all is
// valid UTF-8.
std::size_t FirstInvalidUtf8(std::string_view text);

}  // namespace tpcal
