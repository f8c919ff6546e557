"""Layer 4 — the domain: campaigns and their segments, procedures, metrics, results and
outcomes, the run record (provenance) and the hook specifications a plugin implements.
"""
