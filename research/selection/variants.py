"""Named selection variants: candidates (t_lo, pyramid) and a policy with its parameters."""

VARIANTS: dict[str, dict] = {}


def add(name, policy, budget=1000, t_lo=20, **kw):
    VARIANTS[name] = {"policy": policy, "budget": budget, "t_lo": t_lo, "kw": kw}


for m, tag in (("sad", "sad"), ("harris:7", "h7"), ("harris:5", "h5"), ("harris:5:sm", "h5sm"), ("harris:3", "h3"),
               ("harris:7:sm", "h7sm")):
    add(f"topn-{tag}", "topn", measure=m)
    for lo in (20, 7, 10, 14):
        two = lo < 20
        sfx = f"-lo{lo}" if two else ""
        for k in (1, 2, 3, 4):
            add(f"quota-k{k}-{tag}{sfx}", "quota", t_lo=lo, measure=m, kcell=k, two_thr=two)
        for c in (16, 24, 32, 48, 64):
            for k in (1, 2, 3, 4, 8):
                add(f"band-c{c}-k{k}-{tag}{sfx}", "band", t_lo=lo, measure=m, cell=c, kcell=k, two_thr=two)
                add(f"bandnc-c{c}-k{k}-{tag}{sfx}", "band", t_lo=lo, measure=m, cell=c, kcell=k, two_thr=two,
                    carry=False)
                add(f"bands2-c{c}-k{k}-{tag}{sfx}", "band", t_lo=lo, measure=m, cell=c, kcell=k, two_thr=two,
                    slack=2.0)
        add(f"qt-{tag}{sfx}", "quadtree", t_lo=lo, measure=m, two_thr=two)

for m, tag in (("sad", "sad"), ("harris:5", "h5"), ("harris:7", "h7")):
    for lo in (20, 7):
        two = lo < 20
        sfx = f"-lo{lo}" if two else ""
        for c in (16, 32, 64, 80, 128):
            for k in (1, 2, 4, 8, 16, 32, 64):
                for rm in ("all", "first", "none"):
                    for br in (1, 2, 4, 100):
                        add(f"b-{rm}-r{br}-c{c}-k{k}-{tag}{sfx}", "band", t_lo=lo, measure=m, cell=c, kcell=k,
                            two_thr=two, rank_major=rm, band_rows=br)

for m, tag in (("sad", "sad"), ("harris:5", "h5"), ("harris:7", "h7")):
    for lo in (20, 7, 10):
        two = lo < 20
        sfx = f"-lo{lo}" if two else ""
        for g in ((8, 6), (4, 3), (16, 12), (12, 9)):
            for res in (True, False):
                add(f"fl-g{g[0]}x{g[1]}{'' if res else '-nr'}-{tag}{sfx}", "floor", t_lo=lo, measure=m, grid=g,
                    two_thr=two, reserve=res)
        for c in (32, 48, 64, 80, 96, 128):
            for res in (True, False):
                add(f"fl-c{c}{'' if res else '-nr'}-{tag}{sfx}", "floor", t_lo=lo, measure=m, cell=c, two_thr=two,
                    reserve=res)

for m in ("harris:3", "harris:5", "harris:7", "harris:5:sm", "harris:7:sm", "harris:5:raw:2", "harris:5:raw:2:q3",
          "harris:5:raw:2:q2", "harris:5:raw:2:q4", "harris:5:raw:0:q3", "harris:7:raw:2:q3", "harris:5:sm:2:q3",
          "harris:5:raw:3:q3", "sad"):
    tag = m.replace("harris:", "h").replace(":", "")
    add(f"topn-{tag}", "topn", measure=m)
    for c in (64, 80, 96):
        for lo in (7, 10, 14, 20):
            add(f"fl-c{c}-nr-{tag}-lo{lo}", "floor", t_lo=lo, measure=m, cell=c, two_thr=lo < 20, reserve=False)

for m in ("harris:5:sm:2:q3", "harris:5:raw:2:q3", "harris:5:sm:2:q2", "harris:5:raw:2:q2", "harris:5:raw:2:q1"):
    tag = m.replace("harris:", "h").replace(":", "")
    add(f"topn-{tag}", "topn", measure=m)
    add(f"fl-c80-nr-{tag}-lo7", "floor", t_lo=7, measure=m, cell=80, two_thr=True, reserve=False)

# the golden model's own grid selection (exact streaming semantics), response code with B mantissa bits
for b in (1, 2, 3):
    for c in (48, 64, 80, 96, 128):
        for lo in (7, 10, 20):
            add(f"model-b{b}-c{c}-lo{lo}", "model", t_lo=lo, mbits=b, cell=c)
            add(f"model-b{b}-c{c}-lo{lo}-n1500", "model", budget=1500, t_lo=lo, mbits=b, cell=c)

# gradient precision: >> 3 (8-bit gradients, two products per DSP48) with sums >> 3
add("model-b1-c80-lo7-g3", "model", t_lo=7, mbits=1, cell=80, gshift=3, sshift=3)
add("model-b1-c80-lo7-g3s4", "model", t_lo=7, mbits=1, cell=80, gshift=3, sshift=4)
