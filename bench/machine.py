"""The machine line written next to benchmark results (GPL-2.0-or-later)."""
import os
import time


def machine_line(yade_version=None, threads=None):
    """'cpu model; cores; date UTC; load average[; YADE version, threads]'."""
    model = "?"
    try:
        with open("/proc/cpuinfo") as f:
            for line in f:
                if line.startswith("model name"):
                    model = line.split(":", 1)[1].strip()
                    break
    except OSError:
        pass
    s = "%s; %d cores; %s UTC; load average %s" % (model, os.cpu_count() or 0, time.strftime("%Y-%m-%d %H:%M", time.gmtime()),
                                                    " ".join("%.2f" % x for x in os.getloadavg()))
    if yade_version is not None:
        s += "; YADE %s, %d thread(s)" % (yade_version, threads or 1)
    return s + "\n"
