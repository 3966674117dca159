.PROGRAM mm_fmt(.v,.$s)
  ; Internal (krlkit Mech-Mind package; do not edit): a number as request text, whole numbers
  ; bare, others with 4 decimals; the blanks $ENCODE pads with are trimmed.
  IF .v == INT(.v) THEN
    .$s = $ENCODE(/L, .v)
  ELSE
    .$s = $ENCODE({{ p.real_format }}, .v)
  END
  WHILE $LEFT(.$s, 1) == " " DO
    .$s = $RIGHT(.$s, LEN(.$s) - 1)
  END
  WHILE $RIGHT(.$s, 1) == " " DO
    .$s = $LEFT(.$s, LEN(.$s) - 1)
  END
.END
.PROGRAM mm_tx_begin(.cmd)
  ; Internal: start a request with its command number.
  mm_tx_n = 1
  .$s = ""
  CALL mm_fmt(.cmd, .$s)
  $mm_tx[1] = .$s
.END
.PROGRAM mm_tx_add(.v)
  ; Internal: append ",value" to the request. A request is sent as string pieces of at most
  ; {{ p.piece_max }} characters (plus the final CR).
  .$s = ""
  CALL mm_fmt(.v, .$s)
  IF LEN($mm_tx[mm_tx_n]) + LEN(.$s) + 1 > {{ p.piece_max }} THEN
    mm_tx_n = mm_tx_n + 1
    $mm_tx[mm_tx_n] = ""
  END
  $mm_tx[mm_tx_n] = $mm_tx[mm_tx_n] + "," + .$s
.END
.PROGRAM mm_tx_zero(.n)
  ; Internal: append .n zeros (no robot pose).
  FOR .i = 1 TO .n
    CALL mm_tx_add(0)
  END
.END
.PROGRAM mm_tx_jnt(.#j)
  ; Internal: append J1..J6 (deg).
  DECOMPOSE .v[1] = .#j
  FOR .i = 1 TO 6
    CALL mm_tx_add(.v[.i])
  END
.END
.PROGRAM mm_tx_pose(.&p)
  ; Internal: append X, Y, Z (mm), O, A, T (deg).
  DECOMPOSE .v[1] = .p
  FOR .i = 1 TO 6
    CALL mm_tx_add(.v[.i])
  END
.END
.PROGRAM mm_tx_here(.joints)
  ; Internal: append the current joints (when .joints = 1), then the current flange pose.
  IF .joints == 1 THEN
    HERE .#cur
    CALL mm_tx_jnt(.#cur)
  END
  HERE .cur
  CALL mm_tx_pose(.&cur)
.END
.PROGRAM mm_connect(.st)
  ; Internal: open the connection unless it is open; .st = 0 or {{ p.codes.no_connection }} (NO_CONNECTION).
  .st = 0
  IF mm_sock < 0 THEN
    .sock = -1
    TCP_CONNECT .sock, mm_port, mm_ip[1], {{ p.connect_timeout }}
    IF .sock < 0 THEN
      .st = {{ p.codes.no_connection }}
    ELSE
      mm_sock = .sock
    END
  END
.END
.PROGRAM mm_close()
  ; Internal: close the connection; the next exchange opens a new one.
  IF mm_sock >= 0 THEN
    .ret = 0
    TCP_CLOSE .ret, mm_sock
  END
  mm_sock = -1
.END
.PROGRAM mm_xchg(.cmd,.st)
  ; Internal: send $mm_tx[1..mm_tx_n] with a final CR, read the reply into
  ; mm_fld[1..mm_fld_n] and check that it answers .cmd. .st = 0 when mm_fld[1] echoes .cmd
  ; and mm_fld[2] exists; otherwise a package status code. Every wait is bounded: connect
  ; {{ p.connect_timeout }} s, send and each receive {{ p.reply_timeout }} s.
  .st = 0
  mm_fld_n = 0
  IF mm_skt_ok <> 1 THEN
    .st = {{ p.codes.no_connection }}
    RETURN
  END
  $mm_tx[mm_tx_n] = $mm_tx[mm_tx_n] + $CHR(13)
  CALL mm_connect(.st)
  IF .st <> 0 THEN
    RETURN
  END
  .ret = 0
  TCP_SEND .ret, mm_sock, $mm_tx[1], mm_tx_n, {{ p.reply_timeout }}
  IF .ret < 0 THEN
    ; The server may have closed an idle connection: reconnect once and send again.
    CALL mm_close
    CALL mm_connect(.st)
    IF .st <> 0 THEN
      RETURN
    END
    .ret = 0
    TCP_SEND .ret, mm_sock, $mm_tx[1], mm_tx_n, {{ p.reply_timeout }}
    IF .ret < 0 THEN
      CALL mm_close
      .st = {{ p.codes.send_failed }}
      RETURN
    END
  END
  CALL mm_recv(.st)
  IF .st == 0 THEN
    IF mm_fld_n < 2 THEN
      .st = {{ p.codes.bad_reply }}
    ELSE
      IF mm_fld[1] <> .cmd THEN
        .st = {{ p.codes.wrong_echo }}
      END
    END
  END
  IF .st <> 0 THEN
    ; A late or half-read reply must not answer the next command.
    CALL mm_close
  END
.END
.PROGRAM mm_recv(.st)
  ; Internal: receive until CR and split the reply into mm_fld. Each TCP_RECV waits at most
  ; {{ p.reply_timeout }} s and must bring data; more than {{ p.reply_max }} characters (plus one per
  ; element) without a CR is a bad reply, so the loop ends.
  .st = 0
  .done = 0
  .bytes = 0
  .$acc = ""
  WHILE (.done == 0) AND (.st == 0) DO
    .ret = 0
    .n = 0
    TCP_RECV .ret, mm_sock, .$rb[1], .n, {{ p.reply_timeout }}, {{ p.recv_chunk }}
    IF (.ret < 0) OR (.n <= 0) THEN
      .st = {{ p.codes.reply_timeout }}
    ELSE
      .i = 1
      WHILE (.i <= .n) AND (.done == 0) AND (.st == 0) DO
        .bytes = .bytes + LEN(.$rb[.i]) + 1
        CALL mm_feed(.$rb[.i], .$acc, .done, .st)
        .i = .i + 1
      END
      IF (.done == 0) AND (.st == 0) AND (.bytes > {{ p.reply_max }}) THEN
        .st = {{ p.codes.bad_reply }}
      END
    END
  END
.END
.PROGRAM mm_feed(.$s,.$acc,.done,.st)
  ; Internal: split one received piece on ',' into mm_fld; .$acc carries an unfinished field
  ; to the next piece; CR ends the reply (anything after it is dropped).
  .$t = .$s
  .$f = $DECODE(.$t, $CHR(13), 0)
  .cr = 0
  IF LEN(.$t) > 0 THEN
    .cr = 1
  END
  .$t = .$f
  WHILE (LEN(.$t) > 0) AND (.st == 0) DO
    .$f = $DECODE(.$t, ",", 0)
    .$acc = .$acc + .$f
    IF LEN(.$t) > 0 THEN
      ; Drop exactly the one ',' that ends this field.
      .$t = $RIGHT(.$t, LEN(.$t) - 1)
      CALL mm_field(.$acc, 0, .st)
      .$acc = ""
    END
    IF LEN(.$acc) > {{ p.field_max }} THEN
      .st = {{ p.codes.bad_reply }}
    END
  END
  IF (.st == 0) AND (.cr == 1) THEN
    CALL mm_field(.$acc, 1, .st)
    .$acc = ""
    .done = 1
  END
.END
.PROGRAM mm_field(.$f,.last,.st)
  ; Internal: check one field and append its value to mm_fld. A field is an optional sign,
  ; digits with at most one '.', and blanks; the last field may be empty after a trailing ','.
  ; Loops that may run zero times are WHILE loops (a FOR from 1 to 0 is not relied on).
  .$num = ""
  .digits = 0
  .dots = 0
  .bad = 0
  .i = 1
  WHILE .i <= LEN(.$f) DO
    .c = ASC($MID(.$f, .i, 1))
    IF (.c >= 48) AND (.c <= 57) THEN
      .digits = .digits + 1
      .$num = .$num + $CHR(.c)
    ELSE
      IF (.c == 43) OR (.c == 45) THEN
        IF LEN(.$num) > 0 THEN
          .bad = 1
        END
        .$num = .$num + $CHR(.c)
      ELSE
        IF .c == 46 THEN
          .dots = .dots + 1
          .$num = .$num + "."
        ELSE
          IF (.c <> 32) AND (.c <> 9) AND (.c <> 10) THEN
            .bad = 1
          END
        END
      END
    END
    .i = .i + 1
  END
  IF .digits == 0 THEN
    IF (.last == 1) AND (LEN(.$num) == 0) AND (.bad == 0) AND (mm_fld_n > 0) THEN
      RETURN
    END
    .bad = 1
  END
  IF (.bad == 1) OR (.dots > 1) THEN
    .st = {{ p.codes.bad_reply }}
    RETURN
  END
  IF mm_fld_n >= {{ p.field_cap }} THEN
    .st = {{ p.codes.too_many_points }}
    RETURN
  END
  mm_fld_n = mm_fld_n + 1
  mm_fld[mm_fld_n] = VAL(.$num)
.END
.PROGRAM mm_fetch(.cmd,.ok,.nargs,.a1,.a2,.kind,.pos_num,.vispos,.st)
  ; Internal: the 102/105/205 batch fetch of mm_get_visdata, mm_get_vispath, mm_get_vizdata.
  ; Repeats the request until the server reports all sent; every reply must add points and
  ; the storage holds {{ p.point_cap }}, so the loop ends. .kind: {{ p.kind_joints }} joints, {{ p.kind_tcp }} TCPs.
  .pos_num = 0
  .vispos = 0
  .st = 0
  .k = 0
  .more = 1
  WHILE .more == 1 DO
    .more = 0
    CALL mm_tx_begin(.cmd)
    IF .nargs >= 1 THEN
      CALL mm_tx_add(.a1)
    END
    IF .nargs >= 2 THEN
      CALL mm_tx_add(.a2)
    END
    CALL mm_xchg(.cmd, .st)
    IF .st == 0 THEN
      .st = mm_fld[2]
    END
    IF .st == .ok THEN
      CALL mm_batch(.k, .kind, .vispos, .more, .st)
    END
  END
  IF .st == .ok THEN
    mm_pos_num = .k
    mm_pos_kind = .kind
    .pos_num = .k
  ELSE
    .vispos = 0
  END
.END
.PROGRAM mm_batch(.k,.kind,.vispos,.more,.st)
  ; Internal: store the points of one 102/105/205 reply after the .k stored so far. Reply:
  ; echo, status, all sent, count, Vision Move position, then {{ p.point_fields }} numbers per point (6 pose
  ; values, label, speed). Leaves .st alone on success.
  IF mm_fld_n < {{ p.batch_header }} THEN
    .st = {{ p.codes.bad_reply }}
    RETURN
  END
  .n = mm_fld[4]
  IF (.n < 0) OR (mm_fld_n <> {{ p.batch_header }} + {{ p.point_fields }} * .n) THEN
    .st = {{ p.codes.bad_reply }}
    RETURN
  END
  IF (.n > {{ p.batch_size }}) OR (.k + .n > {{ p.point_cap }}) THEN
    .st = {{ p.codes.too_many_points }}
    RETURN
  END
  IF (.n == 0) AND (mm_fld[3] == 0) THEN
    ; No points but more announced: the loop would not end.
    .st = {{ p.codes.bad_reply }}
    RETURN
  END
  IF .k == 0 THEN
    ; The stored points are being replaced.
    mm_pos_num = 0
    mm_pos_kind = 0
  END
  .i = 1
  WHILE .i <= .n DO
    .f = {{ p.batch_header }} + {{ p.point_fields }} * (.i - 1)
    .p = .k + .i
    IF .kind == {{ p.kind_joints }} THEN
      vis_pos_j1[.p] = mm_fld[.f + 1]
      vis_pos_j2[.p] = mm_fld[.f + 2]
      vis_pos_j3[.p] = mm_fld[.f + 3]
      vis_pos_j4[.p] = mm_fld[.f + 4]
      vis_pos_j5[.p] = mm_fld[.f + 5]
      vis_pos_j6[.p] = mm_fld[.f + 6]
    ELSE
      vis_pos_x[.p] = mm_fld[.f + 1]
      vis_pos_y[.p] = mm_fld[.f + 2]
      vis_pos_z[.p] = mm_fld[.f + 3]
      vis_pos_o[.p] = mm_fld[.f + 4]
      vis_pos_a[.p] = mm_fld[.f + 5]
      vis_pos_t[.p] = mm_fld[.f + 6]
    END
    mm_pos_label[.p] = mm_fld[.f + 7]
    vis_pos_spd[.p] = mm_fld[.f + 8]
    .i = .i + 1
  END
  ; The Vision Move position is 1-based in the whole path in the first reply and in the
  ; remaining waypoints in later ones.
  IF (.vispos == 0) AND (mm_fld[5] > 0) THEN
    .vispos = .k + mm_fld[5]
  END
  .k = .k + .n
  IF mm_fld[3] == 0 THEN
    .more = 1
  END
.END
.PROGRAM mm_plan_wp(.cmd,.fmt,.k,.vispos,.more,.st)
  ; Internal: store the waypoint of one 210/111 reply as waypoint .k + 1 of mm_get_plandata.
  ; Reply: echo, status, all sent, waypoint type (1 = Vision Move), 6 pose values, motion
  ; type, tool, speed, [{{ p.plan_len }} Vision Move values], and for 210 [N, N custom values]. Leaves .st
  ; alone on success.
  IF mm_fld_n < {{ p.plan_fixed }} THEN
    .st = {{ p.codes.bad_reply }}
    RETURN
  END
  .vm = 0
  IF mm_fld[4] == 1 THEN
    .vm = 1
  END
  .plan = 0
  IF .cmd == 210 THEN
    ; Mech-Viz sends Vision Move data on Vision Move waypoints of formats 3 and 4.
    IF (.fmt >= 3) AND (.vm == 1) THEN
      .plan = 1
    END
  ELSE
    ; Mech-Vision: told by the length.
    IF mm_fld_n == {{ p.plan_fixed }} + {{ p.plan_len }} THEN
      .plan = 1
    END
  END
  .idx = {{ p.plan_fixed }} + 1
  IF .plan == 1 THEN
    .idx = .idx + {{ p.plan_len }}
  END
  .n = 0
  IF .cmd == 210 THEN
    ; 210 always ends in N and N custom values; a reply without N (e.g. Vision Move data in
    ; another layout) would otherwise be misread field by field.
    IF mm_fld_n < .idx THEN
      .st = {{ p.codes.bad_reply }}
      RETURN
    END
    .n = mm_fld[.idx]
    IF (.n < 0) OR (mm_fld_n <> .idx + .n) THEN
      .st = {{ p.codes.bad_reply }}
      RETURN
    END
  ELSE
    IF mm_fld_n <> .idx - 1 THEN
      .st = {{ p.codes.bad_reply }}
      RETURN
    END
  END
  IF (.n > {{ p.user_data_len }}) OR (.k >= {{ p.point_cap }}) THEN
    .st = {{ p.codes.too_many_points }}
    RETURN
  END
  IF .k == 0 THEN
    ; The stored points are being replaced.
    mm_pos_num = 0
    mm_pos_kind = 0
  END
  .k = .k + 1
  IF (.fmt == 1) OR (.fmt == 3) THEN
    vis_pos_j1[.k] = mm_fld[5]
    vis_pos_j2[.k] = mm_fld[6]
    vis_pos_j3[.k] = mm_fld[7]
    vis_pos_j4[.k] = mm_fld[8]
    vis_pos_j5[.k] = mm_fld[9]
    vis_pos_j6[.k] = mm_fld[10]
  ELSE
    vis_pos_x[.k] = mm_fld[5]
    vis_pos_y[.k] = mm_fld[6]
    vis_pos_z[.k] = mm_fld[7]
    vis_pos_o[.k] = mm_fld[8]
    vis_pos_a[.k] = mm_fld[9]
    vis_pos_t[.k] = mm_fld[10]
  END
  vis_pos_type[.k] = mm_fld[11]
  vis_pos_tool[.k] = mm_fld[12]
  vis_pos_spd[.k] = mm_fld[13]
  vis_pos_vismove[.k] = .vm
  mm_pos_label[.k] = 0
  FOR .j = 1 TO {{ p.plan_len }}
    vis_plan_result[.k,.j] = 0
    IF .plan == 1 THEN
      vis_plan_result[.k,.j] = mm_fld[{{ p.plan_fixed }} + .j]
    END
  END
  num_customdata[.k] = .n
  .j = 1
  WHILE .j <= .n DO
    vis_custom_data[.k,.j] = mm_fld[.idx + .j]
    .j = .j + 1
  END
  IF (.vispos == 0) AND (.vm == 1) THEN
    .vispos = .k
  END
  IF mm_fld[3] == 0 THEN
    .more = 1
  END
.END
