import symdyn

# Work against precision: the slider-crank's scenario at five tolerances,
# written in Python; no file, so the rows stay in memory.
tolerances = symdyn.Sweep({
    "scenario": "slider_crank",
    "factors": {"tolerance": {"from": 1e-10, "to": 1e-6, "count": 5, "log": True, "set": "integrator.tolerance"}},
    "keep": {"final": ["q"], "checks": False, "counters": True}}, origin="tolerances")
result = symdyn.sweep(tolerances, workers=2)
print(result.columns[:6])  # ['run', 'status', 'error', 'tolerance', 'end(crank)', 'steps']
for row in result.rows:
    print(row[1], row[3], row[4], row[5])  # ok 1e-10 39.17129013... 1027.0, then fewer steps
