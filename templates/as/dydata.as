{% extends "as/program.as" %}
{% block init %}
{%- for o in r.zero_outs %}
  {{ o }} = 0
{%- endfor %}
{% endblock %}
{% block body %}
  ; One vision point per reply: repeat until the server reports all sent. Every reply adds a
  ; point and .k is capped by the storage, so the loop ends.
  .st = 0
  .k = 0
  .more = 1
  WHILE .more == 1 DO
    .more = 0
    CALL mm_tx_begin({{ r.cmd }})
{%- for t in r.tx %}
    CALL mm_tx_add({{ t }})
{%- endfor %}
    CALL mm_xchg({{ r.cmd }}, .st)
    IF .st == 0 THEN
      .st = mm_fld[2]
    END
    IF .st == {{ r.ok }} THEN
      ; Reply: echo, status, all sent, N, X, Y, Z, O, A, T, label, N values.
      .n = -1
      IF mm_fld_n >= {{ p.dy_fixed }} THEN
        .n = mm_fld[4]
      END
      IF (.n < 0) OR (mm_fld_n <> {{ p.dy_fixed }} + .n) THEN
        .st = {{ p.codes.bad_reply }}
      ELSE
        IF (.n > {{ p.user_data_len }}) OR (.k >= {{ p.point_cap }}) THEN
          .st = {{ p.codes.too_many_points }}
        ELSE
          IF .k == 0 THEN
            ; The stored points are being replaced.
            mm_pos_num = 0
            mm_pos_kind = 0
          END
          .k = .k + 1
          vis_pos_x[.k] = mm_fld[5]
          vis_pos_y[.k] = mm_fld[6]
          vis_pos_z[.k] = mm_fld[7]
          vis_pos_o[.k] = mm_fld[8]
          vis_pos_a[.k] = mm_fld[9]
          vis_pos_t[.k] = mm_fld[10]
          mm_pos_label[.k] = mm_fld[{{ p.dy_fixed }}]
          vis_pos_spd[.k] = 0
          num_customdata[.k] = .n
          .j = 1
          WHILE .j <= .n DO
            vis_custom_data[.k,.j] = mm_fld[{{ p.dy_fixed }} + .j]
            .j = .j + 1
          END
          {{ r.arg(".count") }} = .n
          IF mm_fld[3] == 0 THEN
            .more = 1
          END
        END
      END
    END
  END
  IF .st == {{ r.ok }} THEN
    mm_pos_num = .k
    mm_pos_kind = {{ p.kind_tcp }}
    {{ r.arg(".pos_num") }} = .k
  ELSE
    {{ r.arg(".count") }} = 0
  END
{% endblock %}
