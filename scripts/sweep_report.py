"""scripts/sweep_report.py -- what scripts/stability_diagram.py and scripts/poincare.py share: splicing a generated
block into a document between <!-- NAME:begin --> and <!-- NAME:end -->, and importing matplotlib (or saying
clearly that it is missing). Standard library only."""
import re
import sys


def splice(doc, name, text, script):
    """Replaces the block NAME of the markdown file `doc` by `text`; exits naming the file when it has none."""
    old = open(doc).read()
    new, n = re.subn(r"(<!-- %s:begin -->\n).*?(<!-- %s:end -->)" % (name, name),
                     lambda m: m.group(1) + text + "\n" + m.group(2), old, flags=re.S)
    if n != 1:
        sys.exit(f"{script}: {doc} has no <!-- {name}:begin --> ... <!-- {name}:end --> block")
    open(doc, "w").write(new)


def pyplot(png, script, kept):
    """(matplotlib.pyplot, numpy) with the Agg backend, or None after a message on stderr that `png` is not redrawn
    (what is `kept` is still written): Debian's python3-matplotlib imports only under /usr/bin/python3."""
    try:
        import matplotlib
        matplotlib.use("Agg")
        import matplotlib.pyplot as plt
        import numpy as np
    except ImportError as e:
        print(f"{script}: matplotlib/numpy cannot be imported ({e}; Debian: apt-get install python3-matplotlib, run "
              f"under /usr/bin/python3): {kept} is written, {png} is NOT redrawn", file=sys.stderr)
        return None
    return plt, np
