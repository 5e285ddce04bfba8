"""What the whole-font benchmarks share: a command's process tree watched from
``/proc`` while it runs (memory, CPU time per process, when the workers work), and
the line that says how, when and where a report was measured.

:func:`watch` runs a command and samples its process tree every ``interval`` s:
the peak of the tree's summed ``VmRSS`` (a peak shorter than the interval may be
missed), the command process's own peak (``VmHWM``), the CPU time (user + sys) of
the command process and of its descendants (the last value seen of each: a few
tenths of a second of a process's end may be missed), and when the descendants
(the workers) first and last gained CPU time: the *head* (the command's serial
start, before any worker works) and the *tail* (its serial end, after the last
worker's work).  Linux only (``/proc``).
"""

import os
import subprocess
import time

__all__ = ["watch", "measured_header", "started"]

_TICK = os.sysconf("SC_CLK_TCK") if hasattr(os, "sysconf") else 100


def _tree(pid):
    """{pid: (VmRSS kB, CPU s)} of ``pid`` and its descendants."""
    children = {}
    for d in os.listdir("/proc"):
        if not d.isdigit():
            continue
        try:
            with open("/proc/%s/stat" % d) as f:
                fields = f.read().rsplit(")", 1)[1].split()
        except (OSError, IndexError):
            continue
        children.setdefault(int(fields[1]), []).append((int(d), fields))
    out, todo = {}, [pid]
    try:
        with open("/proc/%d/stat" % pid) as f:
            own = f.read().rsplit(")", 1)[1].split()
    except OSError:
        return out
    stats = {pid: own}
    while todo:
        p = todo.pop()
        for c, fields in children.get(p, []):
            stats[c] = fields
            todo.append(c)
    for p, fields in stats.items():
        cpu = (int(fields[11]) + int(fields[12])) / _TICK   # utime, stime
        rss = 0
        try:
            with open("/proc/%d/status" % p) as f:
                for line in f:
                    if line.startswith("VmRSS:"):
                        rss = int(line.split()[1])
        except OSError:
            continue
        out[p] = (rss, cpu)
    return out


def _hwm_kb(pid):
    try:
        with open("/proc/%d/status" % pid) as f:
            return max([0] + [int(line.split()[1]) for line in f if line.startswith("VmHWM:")])
    except OSError:
        return 0


def watch(cmd, env=None, cwd=None, interval=0.1):
    """Run ``cmd`` (stdout and stderr together) and watch its process tree.

    Returns a dict: ``wall`` s, ``cpu`` (the tree's CPU s, from the kernel's
    accounting of the waited-for children, not sampled), ``main_cpu`` and
    ``workers_cpu`` (sampled, see the module docstring), ``tree_mb`` (peak of the
    summed RSS), ``max_mb`` (the command process's VmHWM), ``child_mb`` (the peak
    RSS of any one descendant: a worker, a compiler's subprocess), ``main_rss``
    ([(s, MB)]: the command process's RSS at every sample), ``head`` and ``tail``
    (s: before the first and after the last sample in which a descendant gained
    CPU time; None without descendants that worked), ``line`` (the output's last
    line), ``output`` and ``rc``."""
    import resource

    before = resource.getrusage(resource.RUSAGE_CHILDREN)
    t0 = time.perf_counter()
    proc = subprocess.Popen(cmd, cwd=cwd, env=env, stdout=subprocess.PIPE,
                            stderr=subprocess.STDOUT, text=True)
    import threading

    chunks = []
    reader = threading.Thread(target=lambda: chunks.append(proc.stdout.read()), daemon=True)
    reader.start()
    peak = hwm = child = 0
    main_cpu, workers, samples = 0.0, {}, []
    first = last = None
    while proc.poll() is None:
        now = time.perf_counter() - t0
        tree = _tree(proc.pid)
        peak = max(peak, sum(rss for rss, _ in tree.values()))
        child = max([child] + [rss for p, (rss, _) in tree.items() if p != proc.pid])
        hwm = max(hwm, _hwm_kb(proc.pid))
        samples.append((now, tree.get(proc.pid, (0, 0.0))[0] / 1024.0))
        if proc.pid in tree:
            main_cpu = tree[proc.pid][1]
        gained = False
        for p, (_, cpu) in tree.items():
            if p != proc.pid and cpu > workers.get(p, 0.0):
                workers[p] = cpu
                gained = True
        if gained:
            first = now if first is None else first
            last = now
        time.sleep(interval)
    reader.join()
    wall = time.perf_counter() - t0
    after = resource.getrusage(resource.RUSAGE_CHILDREN)
    cpu = (after.ru_utime - before.ru_utime) + (after.ru_stime - before.ru_stime)
    text = "".join(chunks)
    lines = text.strip().splitlines()
    return {"cpu": cpu, "wall": wall, "main_cpu": main_cpu,
            "workers_cpu": sum(workers.values()), "tree_mb": peak / 1024.0,
            "max_mb": hwm / 1024.0, "child_mb": child / 1024.0, "main_rss": samples,
            "head": first, "tail": None if last is None else wall - last,
            "line": lines[-1] if lines else "", "output": text, "rc": proc.returncode}


def measured_header(title, script, argv, done, planned, note, started):
    """A report's title and its first line: the command (``python -m bench.SCRIPT``
    and ``argv`` without output paths), when (UTC) and at which commit it was
    measured (``started``: :func:`started`'s value when the runs began), how many
    of the planned runs are in it, the machine and its load, and ``note`` (what
    the times mean)."""
    from bench.stroke_profile import shown_args

    return ["# %s (bench/%s.py)" % (title, script), "",
            "Command: `python -m bench.%s%s`; measured %s to %s UTC at %s (%d of %d runs "
            "done).  Machine: %d CPUs shared with other jobs (load average %s at the end): %s"
            % (script, "".join(" " + a for a in shown_args(argv)), started[0],
               time.strftime("%H:%M", time.gmtime()), started[1], done, planned,
               os.cpu_count() or 1, ", ".join("%.1f" % v for v in os.getloadavg()), note)]


def started():
    """(UTC date and time, code version) as the runs begin: the code measured is the
    code at the start (a commit made while a long run goes on is not in it)."""
    from bench.stroke_profile import code_version

    return time.strftime("%Y-%m-%d %H:%M", time.gmtime()), code_version()
