"""Layer 3 — uncertainty budgets (JJF 1059.1 / GUM), the choice of a linear range, and
conformity decisions with their rules.
"""
