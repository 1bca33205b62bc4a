#!/usr/bin/env python3
# SPDX-License-Identifier: MIT
"""ecmxf-util scope's live view on a pseudo-terminal (ctest test-scope-live).

ecmxf-util runs with a pty as its controlling terminal, stdin, stdout and
stderr: by default it draws (braille dots, the cursor hidden); 'q' and
Ctrl-C (the pty's ^C: SIGINT from the terminal) each end the recording with
the CSV and SVG written and exit 0, the terminal's mode as it was before
(tcgetattr on the pty) and the cursor shown again. --no-live on the pty
draws nothing; --live into a pipe draws; the contradictory options are
refused (exit 2). A stalled terminal (a pty whose master side is not read,
its buffer full: the drawing thread's write blocks) does not stall the
recording: its CSV is written whole, the bus times continuous, while
nothing is read, and the last frame is drawn once the pty is read again.

Usage: test_scope_live.py ECMXF_UTIL
"""
import fcntl
import os
import re
import select
import struct
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


def spawn_on_pty(args, rows=None, cols=None):
    """Starts ecmxf-util ARGS with a new pty (of ROWS x COLS when given) as
    its controlling terminal, stdin, stdout and stderr. Returns (master,
    slave, process, termios before)."""
    master, slave = os.openpty()
    termios.tcsetattr(slave, termios.TCSANOW, termios.tcgetattr(slave))
    if rows is not None:
        fcntl.ioctl(slave, termios.TIOCSWINSZ, struct.pack('HHHH', rows, cols, 0, 0))
    before = termios.tcgetattr(slave)

    def controlling_tty():
        fcntl.ioctl(0, termios.TIOCSCTTY, 0)

    p = subprocess.Popen([UTIL] + args, stdin=slave, stdout=slave, stderr=slave, start_new_session=True,
                         preexec_fn=controlling_tty, close_fds=True)
    return master, slave, p, before


def read_until_exit(master, p, args, timeout, what, on_output=None):
    """Reads the pty's output until ecmxf-util exited and nothing is left,
    for at most TIMEOUT seconds (then kills it: WHAT failed); ON_OUTPUT(out)
    is called after each read. Returns the output."""
    out, end = b'', time.monotonic() + timeout
    while time.monotonic() < end:
        r, _, _ = select.select([master], [], [], 0.1)
        if r:
            try:
                chunk = os.read(master, 65536)
            except OSError:
                chunk = b''
            out += chunk
        if on_output:
            on_output(out)
        if p.poll() is not None and not r:
            break
    if p.poll() is None:
        p.kill()
        p.wait()
        check(False, 'ecmxf-util %s %s' % (' '.join(args), what))
    return out


def close_pty(master, slave):
    """termios after the run, then both ends closed."""
    after = termios.tcgetattr(slave)
    os.close(master)
    os.close(slave)
    return after


def on_pty(args, feed=None, wait_for=BRAILLE, timeout=60):
    """Runs ecmxf-util ARGS on a pty; once WAIT_FOR appeared, writes FEED.
    Returns (exit code, output, termios before, termios after)."""
    master, slave, p, before = spawn_on_pty(args)
    fed = [feed is None]

    def feed_when_ready(out):
        if not fed[0] and (wait_for(out) if callable(wait_for) else wait_for in out):
            os.write(master, feed)
            fed[0] = True

    out = read_until_exit(master, p, args, timeout, 'ended within %d s' % timeout, feed_when_ready)
    return p.returncode, out, before, close_pty(master, slave)


def stalled_terminal(args, csv, rows=100, cols=1001, deadline=300):
    """Runs ecmxf-util ARGS on a pty of ROWS x COLS whose master side is not
    read until CSV exists (or DEADLINE seconds passed): a frame of the live
    view then is larger than the pty's buffer, so the first one already
    blocks the write that draws it. Returns (CSV seen while unread, still
    running then, exit code, output, termios before, termios after)."""
    master, slave, p, before = spawn_on_pty(args, rows, cols)
    # not a wall-clock threshold: the deadline only bounds a failing run;
    # a run that works writes the CSV after its cycles, whatever the
    # machine's speed, while nobody reads the terminal
    end = time.monotonic() + deadline
    while not os.path.exists(csv) and p.poll() is None and time.monotonic() < end:
        time.sleep(0.05)
    seen, running = os.path.exists(csv), p.poll() is None
    out = read_until_exit(master, p, args, 60, 'ended once its terminal was read')
    return seen, running, p.returncode, out, before, close_pty(master, slave)


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

    # a stalled terminal: six signals of 8 rows of 1000 braille cells (3
    # bytes each) make a frame of 144 kB, more than a pty holds unread, so
    # the first frame's write blocks until the test reads. The cycles must
    # go on meanwhile: the CSV appears, whole, while the pty is unread (with
    # the drawing in the cycling thread, the first frame blocked the cycle
    # loop before its first cycle: no CSV until the terminal was read)
    csv = os.path.join(d, 'stalled.csv')
    cycles = 3000
    seen, running, rc, out, before, after = stalled_terminal(
        ['-d', 'sim:', 'scope', '0:position_actual_value', '0:following_error_actual_value', '0:statusword',
         '1:position_actual_value', 'wkc', 'rx_fifo', '--cycles', str(cycles), '--csv', csv], csv)
    text = out.decode('utf-8', 'replace')
    check(seen, 'stalled terminal: the CSV written while the terminal was not read')
    check(running, 'stalled terminal: ecmxf-util still waiting to draw then (the terminal was full)')
    check(rc == 0, 'stalled terminal: exit 0 (got %s)' % rc)
    lines = rows(csv) if os.path.exists(csv) else []
    check(len(lines) == cycles + 1, 'stalled terminal: the CSV has all %d samples (got %d)' % (cycles, len(lines) - 1))
    # the first sample comes before the first cycle boundary (950 us on
    # the simulator), every one after it 1 ms after the one before
    times = [float(line.split(',')[0]) for line in lines[1:]]
    steps = {round(b - a, 3) for a, b in zip(times[1:], times[2:])}
    check(len(times) > 2 and steps == {1000.0} and 0 < times[1] - times[0] <= 1000,
          'stalled terminal: the bus times 1 ms apart, no gap (steps %s)' % sorted(steps)[:5])
    check(BRAILLE in out and '%d samples, done' % cycles in text,
          'stalled terminal: the last frame ("done") drawn once the terminal was read')
    check(out.rfind(b'\x1b[?25h') > out.rfind(b'\x1b[?25l') and out.rfind(b'\x1b[?25h') > out.rfind(b', done'),
          'stalled terminal: the cursor shown again after the last frame')
    check(before == after, 'stalled terminal: the terminal mode restored')
    check('%d samples\r\n' % cycles in text and 'LAST' in text, 'stalled terminal: the summary after it')

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
