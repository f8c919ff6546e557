"""Software validation (ISO/IEC 17025 §7.11.2): the cases metro and its plugins ship, run by
``metro validate``, and the validation report that records them."""
