{% extends "as/program.as" %}
{% block body %}
  CALL mm_tx_begin({{ r.cmd }})
  .st = 0
  CALL mm_xchg({{ r.cmd }}, .st)
  ; The reply is the echo and the message, without a status field.
  IF .st == 0 THEN
    {{ r.arg(".msg") }} = mm_fld[2]
  END
{% endblock %}
