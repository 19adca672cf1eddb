#!/bin/sh
# Runs a command on a virtual X server, as `xvfb-run -a -s "-screen 0 1280x720x24"`, and exits with the command's own
# status. xvfb-run alone sometimes exits 5 ("problem while cleaning up temporary directory") after the command has
# ended: Xvfb signals xvfb-run (SIGUSR1) each time it resets, which it does when its last client leaves, and when
# that signal lands while dash waits for xvfb-run's `rm -r` of its folder, the trap runs and `rm` reads as failed
# (measured: 3 of 100 runs with four at once; docs/platform.md, The viewer under Xvfb). The command's status is
# therefore written to a file of our own and read back; without that file (Xvfb did not start) xvfb-run's stands.
status_file=$(mktemp) || exit 1
xvfb-run -a -s "-screen 0 1280x720x24" sh -c '"$@"; echo $? > "$0"' "$status_file" "$@"
xvfb_status=$?
status=$(cat "$status_file")
rm -f "$status_file"
exit "${status:-$xvfb_status}"
