"""The line every benchmark section of bench/results.md starts with: CPU
model, cores, memory, kernel, and the load when the run began (the machine
may be shared, and timings move with it)."""
import os
import platform
import re


def machine():
    cpu = "unknown"
    try:
        with open("/proc/cpuinfo") as f:
            cpu = re.search(r"model name\s*:\s*(.*)", f.read()).group(1)
    except Exception:
        pass
    mem = os.sysconf("SC_PAGE_SIZE") * os.sysconf("SC_PHYS_PAGES") / 2**30
    load = open("/proc/loadavg").read().split()[0]
    return f"{cpu}, {os.cpu_count()} cores, {mem:.0f} GiB, {platform.system()} {platform.release()}; load average {load} at start"


def section_head(what):
    """The heading of a dated section of bench/results.md: UTC time, the
    commit measured, and what made it."""
    import datetime
    import subprocess
    root = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
    commit = subprocess.run(["git", "-C", root, "rev-parse", "--short", "HEAD"], capture_output=True, text=True).stdout.strip()
    return f"\n## {datetime.datetime.now(datetime.timezone.utc):%Y-%m-%d %H:%M} UTC, commit {commit}, {what}"


def append_section(lines, path, write=True):
    """Print a section and, unless told not to, append it to path."""
    text = "\n".join(lines) + "\n"
    print(text)
    if write:
        with open(path, "a") as f:
            f.write(text)
