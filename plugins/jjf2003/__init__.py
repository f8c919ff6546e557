"""JJF 2003—2022 微惯性测量组合(MIMU)校准规范 — plugin `jjf2003`."""
