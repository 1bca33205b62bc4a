#!/usr/bin/env python3
# SPDX-License-Identifier: MIT
"""ecmxf-util scope's live view on a pseudo-terminal (ctest test-scope-live).

ecmxf-util runs with a pty as its controlling terminal, stdin, stdout and
stderr: by default it draws (braille dots, the cursor hidden); 'q' and
Ctrl-C (the pty's ^C: SIGINT from the terminal) each end the recording with
the CSV and SVG written and exit 0, the terminal's mode as it was before
(tcgetattr on the pty) and the cursor shown again. --no-live on the pty
draws nothing; --live into a pipe draws; the contradictory options are
refused (exit 2).

Usage: test_scope_live.py ECMXF_UTIL
"""
import fcntl
import os
import re
import select
import subprocess
import sys
import tempfile
import termios
import time

UTIL = sys.argv[1]
BRAILLE = '\u2800'.encode()[:2]  # E2 A0..A3: the first two bytes of U+2800..U+28FF
failures = []


def check(ok, what):
    print(('ok   ' if ok else 'FAIL ') + what)
    if not ok:
        failures.append(what)


def on_pty(args, feed=None, wait_for=BRAILLE, timeout=60):
    """Runs ecmxf-util ARGS on a pty; once WAIT_FOR appeared, writes FEED.
    Returns (exit code, output, termios before, termios after)."""
    master, slave = os.openpty()
    termios.tcsetattr(slave, termios.TCSANOW, termios.tcgetattr(slave))
    before = termios.tcgetattr(slave)

    def controlling_tty():
        fcntl.ioctl(0, termios.TIOCSCTTY, 0)

    p = subprocess.Popen([UTIL] + args, stdin=slave, stdout=slave, stderr=slave, start_new_session=True,
                         preexec_fn=controlling_tty, close_fds=True)
    out, fed, end = b'', feed is None, time.monotonic() + timeout
    while time.monotonic() < end:
        r, _, _ = select.select([master], [], [], 0.1)
        if r:
            try:
                chunk = os.read(master, 65536)
            except OSError:
                chunk = b''
            out += chunk
        if not fed and (wait_for(out) if callable(wait_for) else wait_for in out):
            os.write(master, feed)
            fed = True
        if p.poll() is not None and not r:
            break
    if p.poll() is None:
        p.kill()
        p.wait()
        check(False, 'ecmxf-util %s ended within %d s' % (' '.join(args), timeout))
    after = termios.tcgetattr(slave)
    os.close(master)
    os.close(slave)
    return p.returncode, out, before, after


def some_samples(out):
    """A frame of the live view says it holds at least 10 samples: only then
    is the key sent, so that the CSV has rows whatever the machine's speed
    (the first frame is drawn before the first cycle)."""
    return any(int(n) >= 10 for n in re.findall(rb'(\d+) samples, ', out))


def rows(path):
    with open(path) as f:
        return f.read().splitlines()


with tempfile.TemporaryDirectory() as d:
    # a long recording on the ECM-XF simulator, ended by a key or Ctrl-C
    for name, key in (('q', b'q'), ('Ctrl-C', b'\x03')):
        csv, svg = os.path.join(d, name + '.csv'), os.path.join(d, name + '.svg')
        rc, out, before, after = on_pty(['-d', 'sim:', 'scope', '0:position_actual_value',
                                         '0:following_error_actual_value', 'wkc', '--cycles', '2000000',
                                         '--buffer', '2000000', '--csv', csv, '--svg', svg], feed=key,
                                        wait_for=some_samples)
        text = out.decode('utf-8', 'replace')
        check(rc == 0, '%s: exit 0 (got %s)' % (name, rc))
        check(b'\x1b[?25l' in out and BRAILLE in out, '%s: the live view drew braille dots' % name)
        check('q or Ctrl-C stops and writes' in text, '%s: the live view says how to stop' % name)
        check('Position actual value' in text and 'Following error actual value' in text,
              '%s: position and following error drawn' % name)
        check(out.rfind(b'\x1b[?25h') > out.rfind(b'\x1b[?25l'), '%s: the cursor shown again at the end' % name)
        check(before == after, '%s: the terminal mode restored' % name)
        check(os.path.exists(csv) and len(rows(csv)) > 2, '%s: the CSV written' % name)
        check(os.path.exists(csv) and len(rows(csv)) < 2000001, '%s: the recording ended early' % name)
        check(os.path.exists(svg) and '</svg>' in open(svg).read(), '%s: the SVG written' % name)
        check('samples' in text and 'LAST' in text, '%s: the summary printed after it' % name)

    # --no-live on a terminal: no drawing, the usual summary
    rc, out, before, after = on_pty(['-d', 'sim:', 'scope', 'wkc', '--cycles', '50', '--no-live'], wait_for=b'\0')
    check(rc == 0, '--no-live: exit 0 (got %s)' % rc)
    check(b'\x1b[' not in out and BRAILLE not in out, '--no-live: nothing drawn')
    check(b'50 samples' in out, '--no-live: the summary')
    check(before == after, '--no-live: the terminal mode untouched')

    # --live into a pipe (no terminal: no keys read, still drawn)
    p = subprocess.run([UTIL, '-d', 'sim:', 'scope', 'wkc', '--cycles', '300', '--live'], stdin=subprocess.DEVNULL,
                       capture_output=True, timeout=60)
    check(p.returncode == 0, '--live into a pipe: exit 0 (got %s: %s)' % (p.returncode, p.stderr))
    check(BRAILLE in p.stdout and b'done' in p.stdout, '--live into a pipe: drawn, the last frame "done"')

    # into a pipe by default: no drawing
    p = subprocess.run([UTIL, '-d', 'sim:', 'scope', 'wkc', '--cycles', '30'], stdin=subprocess.DEVNULL,
                       capture_output=True, timeout=60)
    check(p.returncode == 0 and b'\x1b[' not in p.stdout, 'a pipe: no live view by default')

    # contradictions refused
    for args, msg in ((['--live', '--no-live'], b'--live or --no-live, not both'),
                      (['--live', '--json'], b'--live draws on stdout, where --json writes')):
        p = subprocess.run([UTIL, '-d', 'sim:', 'scope', 'wkc'] + args, capture_output=True, timeout=60)
        check(p.returncode == 2 and msg in p.stderr, '%s: refused, exit 2 (got %s: %s)' % (
            ' '.join(args), p.returncode, p.stderr.decode()))
    p = subprocess.run([UTIL, '-d', 'sim:', 'scope', 'wkc', '--live=yes'], capture_output=True, timeout=60)
    check(p.returncode == 2, '--live=yes: refused, exit 2 (got %s)' % p.returncode)

if failures:
    print('%d check(s) failed' % len(failures))
    sys.exit(1)
print('all checks passed')
