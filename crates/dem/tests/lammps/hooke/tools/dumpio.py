"""Read LAMMPS text dumps (custom per-atom and local) written by the decks."""

def read_dump(path):
    """Return list of (step, header_columns, rows) with rows as lists of strings."""
    frames = []
    with open(path) as f:
        lines = f.read().split("\n")
    i = 0
    while i < len(lines):
        if lines[i].startswith("ITEM: TIMESTEP"):
            step = int(lines[i + 1]); i += 2
            n = int(lines[i + 1]); i += 2
            while not lines[i].startswith("ITEM: ATOMS") and not lines[i].startswith("ITEM: ENTRIES"):
                i += 1
            cols = lines[i].split()[2:]; i += 1
            rows = [lines[i + k].split() for k in range(n)]
            i += n
            frames.append((step, cols, rows))
        else:
            i += 1
    return frames
