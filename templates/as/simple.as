{% extends "as/program.as" %}
{% block body %}
  CALL mm_tx_begin({{ r.cmd }})
{%- for t in r.tx %}
  CALL mm_tx_add({{ t }})
{%- endfor %}
  .st = 0
  CALL mm_xchg({{ r.cmd }}, .st)
  IF .st == 0 THEN
    .st = mm_fld[2]
  END
{%- if !r.out_name.is_empty() %}
  IF .st == {{ r.ok }} THEN
    IF mm_fld_n < {{ r.out_field }} THEN
      .st = {{ p.codes.bad_reply }}
    ELSE
      {{ r.out_name }} = mm_fld[{{ r.out_field }}]
    END
  END
{%- endif %}
{% endblock %}
