#!/bin/sh
# Headless Chromium for the two tests that render a page in it (report.html, the site's
# index): Debian's package, installed by `make test` when it is missing and this user may
# install packages (root, or sudo without a password). Otherwise nothing is installed, the
# two tests are skipped with their reason, and `make test` says so at its end.
# INSTALL_CHROMIUM=no: never install (the tests are then skipped where it is missing).
command -v chromium >/dev/null 2>&1 && exit 0
if [ "${INSTALL_CHROMIUM:-yes}" = no ]; then
  echo "make: chromium not installed (INSTALL_CHROMIUM=no): the 2 browser tests will be skipped"
  exit 0
fi
if [ "$(id -u)" = 0 ]; then
  sudo=""
elif command -v sudo >/dev/null 2>&1 && sudo -n true 2>/dev/null; then
  sudo="sudo -n"
else
  echo "make: chromium is missing and this user cannot install packages: the 2 browser tests" \
       "will be skipped (install Debian's chromium: sudo apt-get install chromium)"
  exit 0
fi
if ! command -v apt-get >/dev/null 2>&1; then
  echo "make: chromium is missing and there is no apt-get: the 2 browser tests will be" \
       "skipped (install Chromium as 'chromium' on the PATH to run them)"
  exit 0
fi
echo "make: installing Debian's chromium (the browser tests render the report and the site in it)"
$sudo apt-get install -y -qq --no-install-recommends chromium >/dev/null 2>&1 \
  || { $sudo apt-get update -qq >/dev/null 2>&1 \
       && $sudo apt-get install -y -qq --no-install-recommends chromium >/dev/null 2>&1; } \
  || echo "make: installing chromium failed: the 2 browser tests will be skipped"
exit 0
