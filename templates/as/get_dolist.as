{% extends "as/program.as" %}
{% block body %}
  ; .resource = 0: Mech-Viz ({{ r.cmd }}); N > 0: Mech-Vision project N ({{ r.alt_cmd }}).
  .cmd = {{ r.cmd }}
  .ok = {{ r.ok }}
  IF {{ r.arg(".resource") }} > 0 THEN
    .cmd = {{ r.alt_cmd }}
    .ok = {{ r.alt_ok }}
  END
  CALL mm_tx_begin(.cmd)
  IF .cmd == {{ r.alt_cmd }} THEN
    CALL mm_tx_add({{ r.arg(".resource") }})
  END
  .st = 0
  CALL mm_xchg(.cmd, .st)
  IF .st == 0 THEN
    .st = mm_fld[2]
  END
  IF .st == .ok THEN
    IF mm_fld_n <> {{ p.do_reply_len }} THEN
      .st = {{ p.codes.bad_reply }}
    ELSE
      FOR .i = 1 TO {{ p.do_list_len }}
        mm_do_list[.i] = mm_fld[.i + 2]
      END
      mm_do_ok = 1
    END
  END
{% endblock %}
