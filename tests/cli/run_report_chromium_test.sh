#!/bin/sh
# report.html opened in headless Chromium: the page's self-check script must set the title to
# "tpcal report: OK (N figures)" (every <svg> drawn, no script error), and a screenshot is taken.
# Negative controls prove the check can fail: an empty figure and a script error each change the
# title. Exit 77 (skipped) when Chromium is not installed.
# Usage: run_report_chromium_test.sh TPCAL SOURCE_DIR WORK_DIR
set -eu
TPCAL=$1; SRC=$2; WORK=$3
fail() { echo "FAIL: $*" >&2; exit 1; }
CHROMIUM=$(command -v chromium || command -v chromium-browser || true)
test -n "$CHROMIUM" || { echo "chromium not installed: skipped"; exit 77; }
rm -rf "$WORK"; mkdir -p "$WORK"
"$TPCAL" -q run "$SRC/samples/pipelines/turning.yaml" --mc-trials 200 --out "$WORK/run" > /dev/null

browse() {  # browse HTML_FILE [--screenshot=PNG]: prints the page title after load
  html=$1; shift
  timeout 90 "$CHROMIUM" --headless --no-sandbox --disable-gpu --disable-background-networking \
    --user-data-dir="$WORK/profile" --window-size=1200,2400 "$@" "file://$html" 2> "$WORK/chromium.err" |
    sed -n 's:.*<title>\(tpcal report[^<]*\)</title>.*:\1:p' | head -1
}

figures=$(grep -c '<svg ' "$WORK/run/report.html")
test "$figures" -ge 5 || fail "report has $figures figures"
title=$(browse "$WORK/run/report.html" --dump-dom)
test "$title" = "tpcal report: OK ($figures figures)" || fail "title '$title' (chromium: $(tail -3 "$WORK/chromium.err"))"

timeout 90 "$CHROMIUM" --headless --no-sandbox --disable-gpu --disable-background-networking \
  --user-data-dir="$WORK/profile" --window-size=1200,2400 --screenshot="$WORK/report.png" \
  "file://$WORK/run/report.html" > /dev/null 2>&1 || fail "screenshot failed"
test "$(wc -c < "$WORK/report.png")" -gt 20000 || fail "screenshot is (nearly) blank"

# Negative controls.
sed 's:</body>:<svg data-figure="empty" width="100" height="100"></svg></body>:' "$WORK/run/report.html" > "$WORK/empty.html"
title=$(browse "$WORK/empty.html" --dump-dom)
case "$title" in "tpcal report: EMPTY FIGURE"*) ;; *) fail "empty figure not detected: '$title'";; esac
sed 's:</body>:<script>no_such_function();</script></body>:' "$WORK/run/report.html" > "$WORK/error.html"
title=$(browse "$WORK/error.html" --dump-dom)
case "$title" in "tpcal report: SCRIPT ERROR"*) ;; *) fail "script error not detected: '$title'";; esac
echo "run_report_chromium: ok ($figures figures, screenshot $WORK/report.png)"
