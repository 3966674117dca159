{% extends "as/program.as" %}
{% block body %}
  ; Handshake: report the current pose (state 0 = start, 1 = reached the point), move to the
  ; joints the server returns, settle, repeat until the server reports calibration done.
  .st = 0
  .state = 0
  .done = 0
  WHILE .done == 0 DO
    .done = 1
    CALL mm_tx_begin({{ p.calib_cmd }})
    CALL mm_tx_add(.state)
    CALL mm_tx_here(0)
    HERE .#cur
    CALL mm_tx_jnt(.#cur)
    CALL mm_xchg({{ p.calib_cmd }}, .st)
    IF .st == 0 THEN
      .st = mm_fld[2]
    END
    IF .st == {{ p.calib_ok }} THEN
      ; Reply: echo, status, done, flange X, Y, Z, O, A, T, joints J1..J6.
      IF mm_fld_n <> {{ p.calib_reply_len }} THEN
        .st = {{ p.codes.bad_reply }}
      ELSE
        IF mm_fld[{{ p.calib_done }}] == 0 THEN
          .j = {{ p.calib_j1 }}
          POINT .#tgt = #PPOINT(mm_fld[.j], mm_fld[.j + 1], mm_fld[.j + 2], mm_fld[.j + 3], mm_fld[.j + 4], mm_fld[.j + 5])
          JMOVE .#tgt
          BREAK
          TWAIT {{ p.calib_wait }}
          .state = 1
          .done = 0
        END
      END
    END
  END
{% endblock %}
