"""The register in a browser (``metro serve``): read-only pages for the lab, and the public page
that verifies a certificate by its number.

:func:`metro.core.web.app.create_app` ``(register_url, *, lab=None)`` makes the Starlette
application (for uvicorn, or Starlette's TestClient); :mod:`metro.core.web.queries` reads the
register through :mod:`metro.core.record` only and never writes.

Routes (GET and HEAD only; POST only on ``/verify/{number}``, whose upload changes nothing; any
other method is 405):

============================================  ======================================================
``/``                                         303 to ``/reports``
``/reports?standard=&serial=&customer=&``     the list, newest issue first, 25 a page (``customer``:
``status=&from=&to=&page=``                   part of the name; ``from``/``to``: measurement dates)
``/reports/{number}``                         one report: status, amendment chain, device, customer,
                                              dates, results (U, k, verdicts), conformity statement,
                                              equipment, downloads
``/reports/{number}/files/{kind}``            ``docx``, ``pdf``, ``dcc``: the registered file, only
                                              when its SHA-256 matches the register (404 none or
                                              missing, 409 changed); the PDF is the DCC's embedded
                                              one, else made from the checked Word file
``/devices/{serial}``                         a device's history (``metro history``): each result
                                              over time with U and |E_n| > 1 drift flags
``/devices/{serial}/history.png``             its plot (matplotlib)
``/equipment``                                the lab's equipment, due dates, what falls due in 30 d
``/verify`` (``?number=``)                    a form for a number; 303 to ``/verify/{number}``
``/verify/{number}``                          public: issued / superseded (by which) / withdrawn;
                                              POST ``file`` (multipart): its SHA-256 against the
                                              register's files, "matches" / "does not match"
============================================  ======================================================

Language: ``?lang=zh|en`` (remembered in the ``metro_lang`` cookie), else the lab's default.

HTML ids and classes the browser tests target:

* every page: ``#nav`` (``#nav-reports``, ``#nav-equipment``, ``#nav-verify``), ``#lang-switch``
  (``#lang-zh``, ``#lang-en``: a link, or ``<strong>`` for the language shown); ``<html lang>``;
  errors: ``#error`` (``data-status``), ``#error-detail``;
* list: ``form#filter`` with ``#f-standard`` (select), ``#f-serial``, ``#f-customer``,
  ``#f-status`` (select), ``#f-from``, ``#f-to`` (date inputs), ``#f-submit``, ``#f-clear``;
  ``#count`` (``data-total``); ``table#reports`` with ``tr.report`` (``data-number``,
  ``data-status``) holding ``a.report-link``, ``td.standard``, ``td.device`` (``a.serial``),
  ``td.customer``, ``td.measured``; ``#no-reports``; ``nav#paging`` with ``a#prev``, ``a#next``,
  ``#page`` (``data-page``, ``data-pages``);
* report: ``#report-number``, ``#report-status`` (``data-status``), ``#withdrawn-reason``,
  ``#standard``, ``#device`` (``a#device-link``), ``#customer``, ``#measured``, ``#issued``;
  ``ol#chain`` of ``li.chain-entry`` (``data-number``; ``.current``; ``.reason``);
  ``table#results`` of ``tr.result`` (``data-item``, ``data-key``) with ``td.value``, ``td.U``,
  ``td.k``, ``td.unit``, ``td.verdict`` (``data-verdict``: ``pass``, ``fail``,
  ``indeterminate`` or empty); ``section#conformity`` (``#overall``, ``data-verdict``);
  ``table#report-equipment`` of ``tr.equipment`` (``td.cal-status``); ``ul#downloads``
  with ``a#download-pdf``, ``a#download-docx``, ``a#download-dcc``; ``#report-sha256``;
  ``a#verify-link``;
* device: ``#serial``, ``img#history-plot``, ``section#history`` of ``table.history``
  (``data-key``) with ``tr.point`` (``.drift`` when |E_n| > 1; ``td.en``); ``ul#calibrations``;
* equipment: ``section#due-soon`` (``li.due-soon`` / ``li.expired``), ``table#equipment`` of
  ``tr.equipment`` (``data-id``, ``data-state``: ``ok``, ``due-soon``, ``expired``, ``no-due``),
  ``#no-lab``;
* verify: ``form#verify-number`` (``input#number``) without a number; ``#verify-status``
  (``data-status``: ``issued``, ``superseded``, ``withdrawn``), ``a#superseded-by``,
  ``#withdrawn-reason``; ``form#upload`` with ``input#upload-file`` (``name="file"``) and
  ``button#upload-submit``; after a POST ``#upload-result`` (``data-match`` ``true``/``false``;
  text "matches" / "does not match" in English) and ``#upload-sha256``.
"""
