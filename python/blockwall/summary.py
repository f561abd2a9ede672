"""The table `tools/plot` prints: the root attributes and the /solver
attributes of a result file, in the order the schema lists them (others
after, alphabetically), with a few derived numbers that say whether the
picture is worth a look."""
import numpy as np

ROOT_ORDER = ["version", "units", "dimension", "m", "m_b", "depth", "scene"]
SOLVER_ORDER = ["method_requested", "method_used", "fallback", "fallback_reason", "iterations", "rtol",
                "residual", "residual_equilibrium", "residual_compatibility", "equilibrium_error", "ranks",
                "unknowns_q", "unknowns_r"]


def _ordered(attrs, order):
    known = [k for k in order if k in attrs]
    # timings in the order of the phases, the total last
    phases = ["generate", "partition", "assemble", "setup", "solve", "recover", "write", "total"]
    rank = {f"seconds_{p}": i for i, p in enumerate(phases)}
    timing = sorted((k for k in attrs if k not in order and k.startswith("seconds_")), key=lambda k: (rank.get(k, len(phases) - 0.5), k))
    rest = sorted(k for k in attrs if k not in order and not k.startswith("seconds_"))
    return known + rest + timing


def _format(v):
    if isinstance(v, float):
        return f"{v:.6g}"
    if isinstance(v, str) and v == "":
        return "-"
    return str(v)


def summary_rows(res):
    """[(section, key, text)]: what summary() prints."""
    rows = []
    for k in _ordered(res.attrs, ROOT_ORDER):
        v = res.attrs[k]
        if k == "scene":  # the whole scene is in the file; one line of it here
            v = f"{len(str(v).splitlines())} lines, title: {res.title or '-'}"
        rows.append(("file", k, _format(v)))
    for k in _ordered(res.solver, SOLVER_ORDER):
        rows.append(("solver", k, _format(res.solver[k])))
    umax = max((float(np.max(np.linalg.norm(res.vertex_displacement(b), axis=1))) for b in range(res.nblocks)), default=0.0)
    rows += [("results", "blocks", str(res.nblocks)), ("results", "interfaces", str(res.ninterfaces)),
             ("results", "max |u| at a vertex [m]", _format(umax))]
    if res.ninterfaces:
        sigma = res.mean_stress()[:, 1]
        rows += [("results", "min mean normal stress [Pa]", _format(float(sigma.min()))),
                 ("results", "max mean normal stress [Pa]", _format(float(sigma.max())))]
    return rows


def summary(res):
    rows = summary_rows(res)
    width = max(len(k) for _, k, _ in rows)
    out, section = [f"{res.path}"], None
    for sec, k, v in rows:
        if sec != section:
            out.append({"file": "root attributes", "solver": "/solver attributes", "results": "results"}[sec])
            section = sec
        out.append(f"  {k:<{width}}  {v}")
    return "\n".join(out)
