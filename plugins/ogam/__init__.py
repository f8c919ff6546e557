"""Draft JJF 光学陀螺测角仪校准规范 (optical-gyro angle measuring instruments) — plugin `ogam`."""
