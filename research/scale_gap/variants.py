from .lib import Opt
G7_64 = (5, 8, 12, 14, 12, 8, 5)      # ~ Gaussian sigma 2, 7 taps, sum 64
G7_40 = (1, 4, 9, 12, 9, 4, 1)        # brief's suggestion, sum 40
G7_32 = (2, 4, 6, 8, 6, 4, 2)         # sum 32
B5 = (1, 4, 6, 4, 1)                  # binomial 5, sigma 1
G5_16 = (3, 3, 4, 3, 3)               # ~ sigma 2 truncated to 5, sum 16
B9 = (1, 8, 28, 56, 70, 56, 28, 8, 1) # binomial 9, sigma sqrt 2, sum 256
G9_64 = (2, 4, 8, 11, 14, 11, 8, 4, 2)  # ~ Gaussian sigma 2, 9 taps, sum 64
VARIANTS = {
    "base": Opt(),
    "x8": Opt(levels=8),
}
# 1. per-level budgets
for n in (4000, 3000, 2000, 1500, 1000):
    for rank in ("sad", "raster", "harris", "harris2x", "cv", "shitomasi"):
        VARIANTS[f"pl{n}-{rank}"] = Opt(select="perlevel", n=n, rank=rank)
    VARIANTS[f"gl{n}-sad"] = Opt(select="global", n=n, rank="sad")
    VARIANTS[f"gl{n}-harris"] = Opt(select="global", n=n, rank="harris")
# 2. thresholds
for t in (10, 15, 25, 30, 40):
    VARIANTS[f"t{t}"] = Opt(thr=t)
for name, th in {"tl20-18-16-14-12-10": (20, 18, 16, 14, 12, 10), "tl20-17-14-12-10-8": (20, 17, 14, 12, 10, 8),
                 "tl25-22-20-18-16-14": (25, 22, 20, 18, 16, 14), "tl30-25-20-18-15-12": (30, 25, 20, 18, 15, 12),
                 "tl20-20-15-15-10-10": (20, 20, 15, 15, 10, 10)}.items():
    VARIANTS[name] = Opt(thr=th)
# 4. descriptor smoothing
for kn, k in {"g7_64": G7_64, "g7_40": G7_40, "g7_32": G7_32, "b5": B5, "g5_16": G5_16, "b9": B9, "g9_64": G9_64}.items():
    VARIANTS[f"desc-{kn}"] = Opt(desc_kernel=k)
    VARIANTS[f"both-{kn}"] = Opt(desc_kernel=k, ori_kernel=k)
# 5. pattern
VARIANTS["pat-cv-sector"] = Opt(pattern="cv-sector")
VARIANTS["pat-cv-angle"] = Opt(pattern="cv-angle")
VARIANTS["pat-cv-angle-g7_64"] = Opt(pattern="cv-angle", desc_kernel=G7_64)
# 7. NMS / score
VARIANTS["nms5"] = Opt(nms=5)
VARIANTS["score-cv"] = Opt(score="cv")
VARIANTS["score-cv-nms5"] = Opt(score="cv", nms=5)
# ---- round 2: combinations and hardware-cheap alternatives
for n in (4000, 3000, 2000, 1500):
    for tn, th in {"c18": (20, 20, 18, 16, 14, 12), "c15": (20, 18, 16, 15, 14, 12), "c10": (20, 18, 15, 13, 11, 10)}.items():
        VARIANTS[f"pl{n}-sad-{tn}"] = Opt(select="perlevel", n=n, rank="sad", thr=th)
        VARIANTS[f"pl{n}-harris2x-{tn}"] = Opt(select="perlevel", n=n, rank="harris2x", thr=th)
    for d in (0.64, 0.72, 0.9):
        VARIANTS[f"pl{n}-sad-d{d}"] = Opt(select="perlevel", n=n, rank="sad", budget_decay=d)
    VARIANTS[f"pl{n}-sad-nms5"] = Opt(select="perlevel", n=n, rank="sad", nms=5)
    VARIANTS[f"pl{n}-harris-b5"] = Opt(select="perlevel", n=n, rank="harris", harris_block=5)
    VARIANTS[f"pl{n}-harris-k16"] = Opt(select="perlevel", n=n, rank="harris", harris_k=(1, 4))
    VARIANTS[f"pl{n}-harris-fk"] = Opt(select="perlevel", n=n, rank="harris", harris_k=(0, 0))
    VARIANTS[f"pl{n}-harris-sm"] = Opt(select="perlevel", n=n, rank="harris", harris_on="smooth")
    VARIANTS[f"pl{n}-scorecv"] = Opt(select="perlevel", n=n, rank="cv", score="cv")
# per-level thresholds without any ranking (hardware-only, no host work): stricter at fine levels
for name, th in {"tp30-25-20-20-20-20": (30, 25, 20, 20, 20, 20), "tp35-28-22-20-18-16": (35, 28, 22, 20, 18, 16),
                 "tp40-32-25-20-16-12": (40, 32, 25, 20, 16, 12), "tp30-26-22-18-15-12": (30, 26, 22, 18, 15, 12),
                 "tp45-35-28-22-18-14": (45, 35, 28, 22, 18, 14), "tp50-40-30-24-18-14": (50, 40, 30, 24, 18, 14)}.items():
    VARIANTS[name] = Opt(thr=th)
VARIANTS["sec64"] = Opt(sectors=64)
VARIANTS["sec16"] = Opt(sectors=16)
for n in (4000, 3000, 2000, 1500):
    VARIANTS[f"pl{n}-sad-sec64"] = Opt(select="perlevel", n=n, rank="sad", sectors=64)
    VARIANTS[f"pl{n}-harris-sec64"] = Opt(select="perlevel", n=n, rank="harris", sectors=64)
    VARIANTS[f"pl{n}-sad-g7_64"] = Opt(select="perlevel", n=n, rank="sad", desc_kernel=G7_64, ori_kernel=G7_64)
    VARIANTS[f"pl{n}-harris-g7_64"] = Opt(select="perlevel", n=n, rank="harris", desc_kernel=G7_64, ori_kernel=G7_64)
    VARIANTS[f"pl{n}-harris-g7_64-sec64"] = Opt(select="perlevel", n=n, rank="harris", desc_kernel=G7_64,
                                                ori_kernel=G7_64, sectors=64)
    VARIANTS[f"pl{n}-sad-g7_64-sec64"] = Opt(select="perlevel", n=n, rank="sad", desc_kernel=G7_64,
                                             ori_kernel=G7_64, sectors=64)
for n in (4000, 3000, 2000, 1500, 1000):
    VARIANTS[f"pl{n}-harrisb5-g7_64-sec64"] = Opt(select="perlevel", n=n, rank="harris", harris_block=5,
                                                  desc_kernel=G7_64, ori_kernel=G7_64, sectors=64)
    VARIANTS[f"pl{n}-harrisb5-g7_64"] = Opt(select="perlevel", n=n, rank="harris", harris_block=5,
                                            desc_kernel=G7_64, ori_kernel=G7_64)
    VARIANTS[f"pl{n}-harrisb5"] = Opt(select="perlevel", n=n, rank="harris", harris_block=5)
    VARIANTS[f"pl{n}-sad-x8"] = Opt(select="perlevel", n=n, rank="sad", levels=8)
    VARIANTS[f"pl{n}-sad-d0.9-g7_64-sec64"] = Opt(select="perlevel", n=n, rank="sad", budget_decay=0.9,
                                                  desc_kernel=G7_64, ori_kernel=G7_64, sectors=64)
VARIANTS["both-g7_64-sec64"] = Opt(desc_kernel=G7_64, ori_kernel=G7_64, sectors=64)
VARIANTS["desc-g7_64-sec64"] = Opt(desc_kernel=G7_64, sectors=64)
VARIANTS["pl4000-sad-g7_64desc-sec64"] = Opt(select="perlevel", n=4000, rank="sad", desc_kernel=G7_64, sectors=64)
VARIANTS["pl3000-sad-g7_64desc-sec64"] = Opt(select="perlevel", n=3000, rank="sad", desc_kernel=G7_64, sectors=64)
VARIANTS["pl5000-sad"] = Opt(select="perlevel", n=5000, rank="sad")
VARIANTS["pl5000-sad-g7_64-sec64"] = Opt(select="perlevel", n=5000, rank="sad", desc_kernel=G7_64, ori_kernel=G7_64, sectors=64)
VARIANTS["pl3000-sad-sec64"] = Opt(select="perlevel", n=3000, rank="sad", sectors=64)
VARIANTS["pl3000-sad-g7_64"] = Opt(select="perlevel", n=3000, rank="sad", desc_kernel=G7_64, ori_kernel=G7_64)
VARIANTS["pl1000-harrisb5"] = Opt(select="perlevel", n=1000, rank="harris", harris_block=5)
VARIANTS["pl1000-sad-g7_64-sec64"] = Opt(select="perlevel", n=1000, rank="sad", desc_kernel=G7_64, ori_kernel=G7_64, sectors=64)
for n in (5000, 4000, 3000):
    VARIANTS[f"pl{n}-sad-x8-g7_64-sec64"] = Opt(select="perlevel", n=n, rank="sad", levels=8, desc_kernel=G7_64,
                                                ori_kernel=G7_64, sectors=64)
VARIANTS["pl5000-sad-x8"] = Opt(select="perlevel", n=5000, rank="sad", levels=8)
VARIANTS["pl4000-harrisb5-x8-g7_64-sec64"] = Opt(select="perlevel", n=4000, rank="harris", harris_block=5, levels=8,
                                                 desc_kernel=G7_64, ori_kernel=G7_64, sectors=64)
# ---- round 3 (main session): what fits the XC7Z020 at 640x480: 4 (and 5) levels of 5:4
for lv in (4, 5):
    for n in (3000, 2000, 1500):
        VARIANTS[f"pl{n}-sad-x{lv}"] = Opt(select="perlevel", n=n, rank="sad", levels=lv)
        VARIANTS[f"pl{n}-sad-x{lv}-sec64"] = Opt(select="perlevel", n=n, rank="sad", levels=lv, sectors=64)
        VARIANTS[f"pl{n}-sad-x{lv}-g7_64-sec64"] = Opt(select="perlevel", n=n, rank="sad", levels=lv,
                                                      desc_kernel=G7_64, ori_kernel=G7_64, sectors=64)
    VARIANTS[f"x{lv}"] = Opt(levels=lv)
for n in (1000, 1200):
    VARIANTS[f"pl{n}-sad-x4-g7_64-sec64"] = Opt(select="perlevel", n=n, rank="sad", levels=4,
                                               desc_kernel=G7_64, ori_kernel=G7_64, sectors=64)
    VARIANTS[f"pl{n}-sad-x5-g7_64-sec64"] = Opt(select="perlevel", n=n, rank="sad", levels=5,
                                               desc_kernel=G7_64, ori_kernel=G7_64, sectors=64)
for d in (0.9, 1.0):
    VARIANTS[f"pl1500-sad-x4-d{d}-g7_64-sec64"] = Opt(select="perlevel", n=1500, rank="sad", levels=4, budget_decay=d,
                                                     desc_kernel=G7_64, ori_kernel=G7_64, sectors=64)
VARIANTS["pl1500-sad-x4-g7_64"] = Opt(select="perlevel", n=1500, rank="sad", levels=4, desc_kernel=G7_64,
                                      ori_kernel=G7_64)
VARIANTS["pl1500-sad-x5-g7_64"] = Opt(select="perlevel", n=1500, rank="sad", levels=5, desc_kernel=G7_64,
                                      ori_kernel=G7_64)
for st in ((3, 2), (7, 4), (5, 4)):
    for n in (1000, 1500):
        VARIANTS[f"pl{n}-sad-{st[0]}{st[1]}x4-g7_64-sec64"] = Opt(step=st, select="perlevel", n=n, rank="sad", levels=4,
                                                                   desc_kernel=G7_64, ori_kernel=G7_64, sectors=64)
        VARIANTS[f"pl{n}-sad-{st[0]}{st[1]}x4-g7_64-sec32"] = Opt(step=st, select="perlevel", n=n, rank="sad", levels=4,
                                                                   desc_kernel=G7_64, ori_kernel=G7_64, sectors=32)
for n in (700, 800, 1200):
    VARIANTS[f"pl{n}-sad-x4-g7_64-sec64"] = Opt(select="perlevel", n=n, rank="sad", levels=4,
                                               desc_kernel=G7_64, ori_kernel=G7_64, sectors=64)
for tn, th in {"t15": 15, "t12": 12, "t18": 18, "c15": (20, 18, 16, 15), "c12": (20, 17, 14, 12), "c10": (20, 16, 13, 10)}.items():
    VARIANTS[f"pl1000-sad-x4-g7_64-sec64-{tn}"] = Opt(select="perlevel", n=1000, rank="sad", levels=4, thr=th,
                                                     desc_kernel=G7_64, ori_kernel=G7_64, sectors=64)
for tn, th in {"t25": 25, "t22": 22}.items():
    VARIANTS[f"pl1000-sad-x4-g7_64-sec64-{tn}"] = Opt(select="perlevel", n=1000, rank="sad", levels=4, thr=th,
                                                     desc_kernel=G7_64, ori_kernel=G7_64, sectors=64)
for d in (0.85, 0.75):
    VARIANTS[f"pl1000-sad-x4-d{d}-g7_64-sec64"] = Opt(select="perlevel", n=1000, rank="sad", levels=4, budget_decay=d,
                                                     desc_kernel=G7_64, ori_kernel=G7_64, sectors=64)
