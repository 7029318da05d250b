#!/usr/bin/env python3
"""How sharply the shear rate at the compact band's inner perimeter picks its leading
azimuthal mode (VALIDATION.md, "Shear bands: ordered (Gaussian) against amorphous").

Reads a run's coarse-grained fields (RUN/frames/fields_*.vts, written by the dispersal
analysis), rebuilds the annulus `shear_bands.rs` searches (the band map of `bands.rs`:
φ averaged over ±1 sector, inner surface at φ ≥ 0.1, band φ ≥ 0.84; the median inner
ring + 1 out to the median last band ring, at most 6 rings; at least 2), takes γ̇
normalised by each ring's mean, averaged over the rings, and its Fourier power per mode.
Per run, over the analysed times in [5, 20] µs (one per half microsecond): the median
of the leading mode (k = 2..90, what `groups` is), the median ratio of its power to the
mean power of modes 2..45 (white noise: about 4.4, the expected largest of 44
exponential powers), and the mean spectral centroid over modes 2..45.

usage: python3 bench/shear_band_spectra.py RUN_DIR [RUN_DIR ...]
No dependencies beyond the standard library.
"""
import cmath, math, os, re, statistics as st, struct, sys


def read_vts(path):
    """Cell arrays of a grains fields_*.vts (raw appended data, UInt64 headers)."""
    b = open(path, 'rb').read()
    end = b.index(b'<AppendedData')
    head = b[:end].decode()
    start = b.index(b'_', end) + 1
    ext = list(map(int, re.search(r'WholeExtent="([^"]*)"', head).group(1).split()))
    out = {'nr': ext[1] - ext[0], 'nt': ext[3] - ext[2]}
    pat = r'<DataArray type="(\w+)" Name="(\w+)" NumberOfComponents="(\d)" format="appended" offset="(\d+)"'
    for ty, name, nc, off in re.findall(pat, head):
        o = start + int(off)
        n = struct.unpack_from('<Q', b, o)[0]
        fmt = {'Float64': 'd', 'Int32': 'i'}[ty]
        vals = struct.unpack_from('<%d%s' % (n // struct.calcsize(fmt), fmt), b, o + 8)
        nc = int(nc)
        out[name] = vals if nc == 1 else [vals[k * nc:(k + 1) * nc] for k in range(len(vals) // nc)]
    return out


def annulus(f):
    """(first ring, rings) of the shear-band annulus, or None."""
    nr, nt, phi = f['nr'], f['nt'], f['packing_fraction']
    ps = [[sum(phi[((j + d) % nt) * nr + i] for d in (-1, 0, 1)) / 3 for i in range(nr)] for j in range(nt)]
    inner, last = [], []
    for j in range(nt):
        i0 = next((i for i in range(nr) if ps[j][i] >= 0.1), None)
        if i0 is None:
            continue
        lst = None
        for i in range(i0, nr):
            if ps[j][i] >= 0.84:
                lst = i
            elif lst is not None and not (i + 1 < nr and ps[j][i + 1] >= 0.84):
                break
        if lst is not None:
            inner.append(i0)
            last.append(lst)
    if not last:
        return None
    first = sorted(inner)[len(inner) // 2] + 1
    rows = min(sorted(last)[len(last) // 2] + 1 - first, 6)
    return (first, rows) if rows >= 2 else None


def power(x):
    n, m = len(x), sum(x) / len(x)
    return [abs(sum((x[j] - m) * cmath.exp(-2j * math.pi * k * j / n) for j in range(n))) ** 2
            for k in range(n // 2 + 1)]


def main():
    for run in sys.argv[1:]:
        frames = os.path.join(run, 'frames')
        pvd = open(os.path.join(frames, 'fields.pvd')).read()
        seen = {}
        for t, name in re.findall(r'timestep="([^"]*)" group="" part="0" file="([^"]*)"', pvd):
            t = float(t)
            if not 4.99e-6 <= t <= 20.01e-6:
                continue
            f = read_vts(os.path.join(frames, name))
            a = annulus(f)
            if a is None:
                continue
            nr, nt, g = f['nr'], f['nt'], f['shear_rate']
            rows = []
            for i in range(a[0], a[0] + a[1]):
                x = [g[j * nr + i] for j in range(nt)]
                fin = [v for v in x if v == v]
                m = sum(fin) / len(fin)
                rows.append([v / m if v == v and m > 0 else 1.0 for v in x])
            s = power([sum(r[j] for r in rows) / len(rows) for j in range(nt)])
            lead = max(range(2, len(s)), key=lambda k: s[k])
            band = s[2:46]
            seen[round(t * 2e6)] = (lead, s[lead] / st.mean(band),
                                    sum(k * p for k, p in enumerate(band, 2)) / sum(band))
        v = list(seen.values())
        print('%s: %d times with a band; leading mode median %s; its power / mean power '
              'k 2-45 median %.1f; centroid k %.1f' % (
                  run, len(v), st.median(x[0] for x in v), st.median(x[1] for x in v),
                  st.mean(x[2] for x in v)))


if __name__ == '__main__':
    main()
